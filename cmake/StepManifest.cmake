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

# raykit_remote_lines(<step.json> <include_dir> <out_var>)
#
# The step's functions as the judge calls them, one `RAYKIT_REMOTE(return type, name, (parameters),
# (arguments))` line each (tests/support/proxies.cpp, answers_main.cpp), derived from the two places
# that already say it: the names are step.json's "functions", the signature each one's declaration in
# a header of <include_dir>/raykit/. So a step lists its functions once and states their types once.
#
# A declaration is read as the kit's headers write one: at the start of a line, `TYPE NAME(PARAMS);`,
# the parameters possibly over several lines, each one named (the proxy forwards them by name). A
# name with no such declaration, or with two, stops the configure with the function's and step's names.
# The step's "functions" (its manifest's list of the functions a student writes), in `out`.
function(raykit_manifest_functions manifest out)
  file(READ "${manifest}" text)
  set(functions "")
  if(text MATCHES "\"functions\"[ \t\r\n]*:[ \t\r\n]*\\[([^]]*)\\]")
    string(REGEX MATCHALL "\"[^\"]*\"" quoted "${CMAKE_MATCH_1}")
    foreach(q IN LISTS quoted)
      string(REGEX REPLACE "^\"(.*)\"$" "\\1" item "${q}")
      list(APPEND functions "${item}")
    endforeach()
  endif()
  set(${out} "${functions}" PARENT_SCOPE)
endfunction()

function(raykit_remote_lines manifest include_dir out)
  raykit_manifest_functions("${manifest}" functions)
  file(GLOB headers "${include_dir}/raykit/*.hpp")
  list(SORT headers)
  set(api "")
  foreach(h IN LISTS headers)
    file(READ "${h}" htext)
    string(APPEND api "\n${htext}")
  endforeach()
  set(lines "")
  foreach(f IN LISTS functions)
    if(NOT f MATCHES "^[A-Za-z_][A-Za-z0-9_]*$")
      message(FATAL_ERROR "raykit: ${manifest}: \"${f}\" in \"functions\" is not a function's name")
    endif()
    set(decl "\n([A-Za-z_][A-Za-z0-9_:<>, ]*[ &*])${f}[ \t]*\\(([^()]*)\\)[ \t\r\n]*;")
    # Counted by a marker: the matches themselves hold a `;`, CMake's list separator.
    string(REGEX REPLACE "${decl}" "\n@raykit_declaration@" marked "${api}")
    string(REGEX MATCHALL "@raykit_declaration@" found "${marked}")
    list(LENGTH found n)
    if(NOT n EQUAL 1)
      message(FATAL_ERROR "raykit: ${manifest} names \"${f}\" in \"functions\", and ${n} declarations "
                          "`TYPE ${f}(PARAMETERS);` begin a line of ${include_dir}/raykit/*.hpp (one is needed)")
    endif()
    string(REGEX MATCH "${decl}" whole "${api}")
    string(STRIP "${CMAKE_MATCH_1}" ret)
    string(REGEX REPLACE "[ \t\r\n]+" " " params "${CMAKE_MATCH_2}")
    string(STRIP "${params}" params)
    if(ret MATCHES "," OR params MATCHES "<[^>]*,")
      message(FATAL_ERROR "raykit: ${f}: a comma inside a template argument (`${ret} ${f}(${params})`) "
                          "cannot pass through RAYKIT_REMOTE: name the type with a `using` in its header")
    endif()
    set(args "")
    if(NOT params STREQUAL "" AND NOT params STREQUAL "void")
      string(REPLACE "," ";" parts "${params}")
      foreach(p IN LISTS parts)
        string(REGEX REPLACE "=.*$" "" p "${p}")
        string(STRIP "${p}" p)
        if(NOT p MATCHES "[^A-Za-z0-9_]([A-Za-z_][A-Za-z0-9_]*)$")
          message(FATAL_ERROR "raykit: ${f}: the parameter `${p}` has no name in its declaration "
                              "(the judge's proxy forwards the parameters by name)")
        endif()
        list(APPEND args "${CMAKE_MATCH_1}")
      endforeach()
    endif()
    string(REPLACE ";" ", " args "${args}")
    string(APPEND lines "RAYKIT_REMOTE(${ret}, ${f}, (${params}), (${args}))\n")
  endforeach()
  set(${out} "${lines}" PARENT_SCOPE)
endfunction()
