# The fuzz targets: every tests/fuzz/fuzz_<name>.cpp defines LLVMFuzzerTestOneInput for target
# <name>; its corpus (seeds and regression inputs) is tests/fuzz/corpus/<name>/.
# capz_fuzz_target(<name> <executable>) adds the include paths and the library to an executable.
file(GLOB CAPZ_FUZZ_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/fuzz_*.cpp)
set(CAPZ_FUZZ_TARGETS "")
foreach(src ${CAPZ_FUZZ_SOURCES})
  get_filename_component(stem ${src} NAME_WE)
  string(REGEX REPLACE "^fuzz_" "" name ${stem})
  list(APPEND CAPZ_FUZZ_TARGETS ${name})
endforeach()

function(capz_fuzz_setup exe)
  target_include_directories(${exe} PRIVATE ${CMAKE_SOURCE_DIR}/src ${CMAKE_SOURCE_DIR}/tests/fuzz)
  target_link_libraries(${exe} PRIVATE capz::capz)
endfunction()
