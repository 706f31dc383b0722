# Reads a step's manifest, tests/NN_topic/step.json, without string(JSON)
# (CMake 3.19+): the two lists CMake needs, "files" and "needs", are flat arrays
# of strings, which a regular expression reads reliably. ./kit test checks that
# this reading agrees with Python's json module for every step.
function(raykit_manifest_list manifest key out)
  file(READ "${manifest}" text)
  string(REGEX MATCH "\"${key}\"[ \t\r\n]*:[ \t\r\n]*\\[[^]]*\\]" entry "${text}")
  set(items "")
  if(entry)
    string(REGEX REPLACE "^[^[]*\\[" "" inner "${entry}")
    string(REGEX MATCHALL "\"[^\"]*\"" quoted "${inner}")
    foreach(q IN LISTS quoted)
      string(REGEX REPLACE "^\"(.*)\"$" "\\1" item "${q}")
      list(APPEND items "${item}")
    endforeach()
  endif()
  set(${out} "${items}" PARENT_SCOPE)
endfunction()
