// stb's PNG reader and writer, compiled once here from its two headers (stb_image.h,
// stb_image_write.h): where the headers come from (Homebrew, vcpkg, a copied folder, Debian's
// libstb-dev) there is then nothing else to install, no compiled library and no pkg-config file.
// Only PNG is needed: the other formats' decoders are left out.
#define STBI_ONLY_PNG
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
