# cmake -DMANIFEST=tests/NN_topic/step.json -P print_manifest.cmake
# Prints what cmake/StepManifest.cmake reads from one manifest, as "files=a;b" and
# "needs=c" lines, so manifest_check.py can compare it with Python's json module.
include("${CMAKE_CURRENT_LIST_DIR}/../../cmake/StepManifest.cmake")
raykit_step_manifest("${MANIFEST}" files needs)
message(STATUS "files=${files}")
message(STATUS "needs=${needs}")
