# Layering (CTest): the folders of src/tsubu/ stand in layers, and a file may include the
# headers of its own folder and of the folders below it, never of one above (docs/engine.md,
# "Layers"). Reads every #include "..." under src/ and fails on one that runs up.
#   cmake -DSOURCE_DIR=<the repository> -P tests/layering.cmake
cmake_minimum_required(VERSION 3.25)

# The layers, lowest first. A file right under src/tsubu/ (version.hpp) counts as core.
set(layers core world search fluid contact integrate io scenario source analysis sim app)

# Includes that still run up, until the World is split into its state and the model beside
# it: the World holds the laws, fluid and search method beside its state. No other may
# be added; one that is gone must leave this list.
set(known_exceptions
    "src/tsubu/world/world.hpp -> tsubu/contact/contact_list.hpp"
    "src/tsubu/world/world.hpp -> tsubu/contact/law.hpp"
    "src/tsubu/world/world.hpp -> tsubu/fluid/fluid.hpp"
    "src/tsubu/world/world.hpp -> tsubu/search/pair_search.hpp")

# The layer index of a path under src/ ("tsubu/<folder>/..."), or -1 for none of them.
function(layer_of path out)
  set(index -1)
  if(path MATCHES "^tsubu/([^/]+)/")
    list(FIND layers "${CMAKE_MATCH_1}" index)
  elseif(path MATCHES "^tsubu/[^/]+$")
    set(index 0)
  endif()
  set(${out} ${index} PARENT_SCOPE)
endfunction()

file(GLOB_RECURSE files RELATIVE "${SOURCE_DIR}/src" "${SOURCE_DIR}/src/*.hpp" "${SOURCE_DIR}/src/*.cpp")
if(NOT files)
  message(FATAL_ERROR "no sources under ${SOURCE_DIR}/src (pass -DSOURCE_DIR=<the repository>)")
endif()
set(failures "")
set(found_exceptions "")
foreach(file IN LISTS files)
  layer_of("${file}" own)
  if(own EQUAL -1)
    list(APPEND failures "src/${file} is in no layer: add its folder to the layers")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/src/${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\".*" "\\1" header "${line}")
    layer_of("${header}" theirs)
    set(include "src/${file} -> ${header}")
    if(theirs EQUAL -1)
      list(APPEND failures "${include}: the header is in no layer")
    elseif(theirs GREATER own)
      list(FIND known_exceptions "${include}" known)
      if(known EQUAL -1)
        list(GET layers ${own} low)
        list(GET layers ${theirs} high)
        list(APPEND failures "${include}: ${low} may not include ${high}, a higher layer")
      else()
        list(APPEND found_exceptions "${include}")
      endif()
    endif()
  endforeach()
endforeach()
foreach(include IN LISTS known_exceptions)
  if(NOT include IN_LIST found_exceptions)
    list(APPEND failures "${include} is listed as a known exception but is gone: take it off the list")
  endif()
endforeach()

list(LENGTH files count)
if(failures)
  list(JOIN failures "\n  " text)
  list(JOIN layers " < " order)
  message(FATAL_ERROR "includes against the layers (${order}):\n  ${text}")
endif()
message(STATUS "${count} files under src/ include only their own layer and those below it")
