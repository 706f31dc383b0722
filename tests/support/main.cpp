// doctest's main lives alone in this file so that it is compiled once per
// build, not once per step.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
