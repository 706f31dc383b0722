# raykit_step_manifest(<step.json> <files_var> <needs_var>)
#
# Reads the two lists the build needs out of a step's manifest
# (tests/NN_topic/step.json): "files" (the sources a student writes) and
# "needs" (the step numbers whose code this step links).
#
# Why not string(JSON ...): it exists only from CMake 3.19, and Debian 11 ships
# 3.18. The manifests are the kit's own, small and regular (a flat object whose
# "files" and "needs" are arrays of plain strings), so a regular expression is
# enough. A manifest it cannot read stops the configure with the file's name
# instead of silently building a step without sources.
function(raykit_step_manifest manifest files_var needs_var)
  file(READ "${manifest}" text)
  foreach(key IN ITEMS files needs)
    # "key": [ ... ]  -- the array holds no brackets, so [^]]* stops at its end.
    if(NOT text MATCHES "\"${key}\"[ \t\r\n]*:[ \t\r\n]*\\[([^]]*)\\]")
      if(key STREQUAL "needs")      # optional: a step that links no other
        set(${key} "")
        continue()
      endif()
      message(FATAL_ERROR "raykit: ${manifest} has no \"${key}\": [...] list")
    endif()
    set(body "${CMAKE_MATCH_1}")
    set(${key} "")
    string(REGEX MATCHALL "\"[^\"]*\"" quoted "${body}")
    foreach(q IN LISTS quoted)
      string(REGEX REPLACE "^\"(.*)\"$" "\\1" item "${q}")
      list(APPEND ${key} "${item}")
    endforeach()
    # Whatever is left once the strings are gone must be commas and spaces;
    # anything else (a number, a nested value) is not a manifest we understand.
    string(REGEX REPLACE "\"[^\"]*\"" "" rest "${body}")
    if(NOT rest MATCHES "^[ \t\r\n,]*$")
      message(FATAL_ERROR "raykit: ${manifest}: \"${key}\" must be a list of strings")
    endif()
  endforeach()
  if(NOT files)
    message(FATAL_ERROR "raykit: ${manifest}: \"files\" is empty")
  endif()
  set(${files_var} "${files}" PARENT_SCOPE)
  set(${needs_var} "${needs}" PARENT_SCOPE)
endfunction()

# raykit_manifest_list(<step.json> <key> <out_var>): one of the two lists, by name.
function(raykit_manifest_list manifest key out)
  raykit_step_manifest("${manifest}" files needs)
  set(${out} "${${key}}" PARENT_SCOPE)
endfunction()
