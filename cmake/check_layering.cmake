# The folder graph is the architecture: every folder library names the folder
# libraries it uses (slipstrip_folder_library in CMakeLists.txt), and this
# script, run as the test folder_layering, fails when
#   * that graph has a cycle, or
#   * a file in a folder includes a header of a folder it does not use,
#     directly or through the folders it uses (an arrow pointing up).
# Usage: cmake -DSOURCE_DIR=<repo> -DGRAPH="io=|friction=|kernels=io|..." -P check_layering.cmake
# (a folder, "=", the folders it uses separated by ","; entries separated by "|").
cmake_minimum_required(VERSION 3.20)
if(NOT SOURCE_DIR OR NOT GRAPH)
  message(FATAL_ERROR "check_layering.cmake needs -DSOURCE_DIR and -DGRAPH")
endif()

string(REPLACE "|" ";" entries "${GRAPH}")
set(folders "")
foreach(entry ${entries})
  string(REGEX MATCH "^([a-z0-9_]+)=(.*)$" _ "${entry}")
  set(folder "${CMAKE_MATCH_1}")
  string(REPLACE "," ";" uses "${CMAKE_MATCH_2}")
  list(APPEND folders ${folder})
  set(uses_${folder} ${uses})
endforeach()

# Everything a folder reaches, by depth-first search; a folder met again on
# the current path is a cycle.
set(failures "")
# (A callee's PARENT_SCOPE is its caller's scope, so failures and
# reached_<folder> travel up the recursion one level per return.)
function(reach folder path)
  list(APPEND path ${folder})
  set(all "")
  foreach(used ${uses_${folder}})
    if(used IN_LIST path)
      list(APPEND path ${used})
      list(JOIN path " -> " cycle)
      string(APPEND failures "cycle in the folder graph: ${cycle}\n")
      continue()
    endif()
    reach(${used} "${path}")
    list(APPEND all ${used} ${reached_${used}})
  endforeach()
  list(REMOVE_DUPLICATES all)
  set(reached_${folder} "${all}" PARENT_SCOPE)
  set(failures "${failures}" PARENT_SCOPE)
endfunction()
foreach(folder ${folders})
  foreach(used ${uses_${folder}})
    if(NOT used IN_LIST folders)
      string(APPEND failures "${folder} uses ${used}, which is not a folder library\n")
    endif()
  endforeach()
endforeach()
foreach(folder ${folders})
  reach(${folder} "")
endforeach()

# Every #include "<folder>/..." of a project folder must stay inside the folder
# or go down to a folder it reaches.
foreach(folder ${folders})
  file(GLOB files ${SOURCE_DIR}/${folder}/*.cpp ${SOURCE_DIR}/${folder}/*.hpp ${SOURCE_DIR}/${folder}/*.inc)
  foreach(file ${files})
    file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include[ \t]+\"[a-z0-9_]+/")
    foreach(line ${lines})
      string(REGEX MATCH "\"([a-z0-9_]+)/([^\"]*)\"" _ "${line}")
      set(target "${CMAKE_MATCH_1}")
      if(target IN_LIST folders AND NOT target STREQUAL folder AND NOT target IN_LIST reached_${folder})
        file(RELATIVE_PATH rel ${SOURCE_DIR} ${file})
        list(JOIN reached_${folder} ", " reached)
        string(APPEND failures "${rel} includes \"${target}/${CMAKE_MATCH_2}\", but ${folder} does not "
                               "use ${target} (it uses: ${reached})\n")
      endif()
    endforeach()
  endforeach()
endforeach()

if(failures)
  message(FATAL_ERROR "folder layering broken:\n${failures}")
endif()
list(LENGTH folders count)
message(STATUS "folder layering: ${count} folders, no cycle, no include pointing up")
