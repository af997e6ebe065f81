# Layers import downward only (docs/ARCHITECTURE.md "Layers"): a source under src/<layer>/ never
# includes a header of a layer above it, and the CLI and the Python module include the public
# headers (capz/...) only. Run as: cmake -DCAPZ_SOURCE_DIR=<repository> -P check_layers.cmake
# (ctest test `layers`, label unit). Fails listing every include that runs up.
cmake_minimum_required(VERSION 3.16)
if(NOT CAPZ_SOURCE_DIR)
  message(FATAL_ERROR "check_layers.cmake: give -DCAPZ_SOURCE_DIR=<repository root>")
endif()

# Lowest first. src/modules/ (capz's PCL modules, built apart) sits with the layer of the
# interface each implements: the PCD module with src/io, the geometry module
# (codec/pcl_geom.h) with src/codec.
set(layers core coding io metrics codec)
set(faults "")

# Appends to `faults` every '#include "<folder>/...' in `file` whose folder is in `forbidden`.
function(check_file file forbidden)
  file(STRINGS "${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]+\"[a-z_]+/")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"([a-z_]+)/.*" "\\1" folder "${line}")
    if(folder IN_LIST forbidden)
      file(RELATIVE_PATH rel "${CAPZ_SOURCE_DIR}" "${file}")
      string(STRIP "${line}" line)
      list(APPEND faults "${rel}: ${line}")
    endif()
  endforeach()
  set(faults "${faults}" PARENT_SCOPE)
endfunction()

list(LENGTH layers count)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  list(GET layers ${i} layer)
  set(above "")
  if(i LESS last)
    math(EXPR next "${i} + 1")
    foreach(j RANGE ${next} ${last})
      list(GET layers ${j} up)
      list(APPEND above ${up})
    endforeach()
  endif()
  set(dirs "${CAPZ_SOURCE_DIR}/src/${layer}")
  foreach(dir IN LISTS dirs)
    file(GLOB_RECURSE sources "${dir}/*.h" "${dir}/*.cpp")
    if(layer STREQUAL "io")
      file(GLOB module_sources "${CAPZ_SOURCE_DIR}/src/modules/*.cpp")
      list(FILTER module_sources EXCLUDE REGEX "/geom_pcl\\.cpp$")
      list(APPEND sources ${module_sources})
    endif()
    foreach(f IN LISTS sources)
      check_file("${f}" "${above}")
    endforeach()
  endforeach()
endforeach()

# The CLI and the Python module: the public API only.
file(GLOB_RECURSE users "${CAPZ_SOURCE_DIR}/apps/*.h" "${CAPZ_SOURCE_DIR}/apps/*.cpp"
     "${CAPZ_SOURCE_DIR}/python/src/*.h" "${CAPZ_SOURCE_DIR}/python/src/*.cpp")
foreach(f IN LISTS users)
  check_file("${f}" "${layers};modules")
endforeach()

if(faults)
  list(LENGTH faults n)
  string(REPLACE ";" "\n  " listing "${faults}")
  message(FATAL_ERROR "${n} include(s) run up the layers (docs/ARCHITECTURE.md):\n  ${listing}")
endif()
message(STATUS "layers: every include runs downward")
