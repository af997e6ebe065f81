# ctest `install` (label install): installs the build tree into a fresh prefix and uses it the way
# a downstream project would, with nothing of the source or build tree on its paths:
#   1. cmake --install BUILD --prefix WORK/prefix
#   2. tests/consumer/ configured with CMAKE_PREFIX_PATH=WORK/prefix (find_package(capz)), built,
#      and run: compress_take (capz::capz) writes two .capz files, decode_take (capz::decode
#      alone) decodes and checks them;
#   3. pkg-config --cflags --libs capz (PKG_CONFIG_PATH=WORK/prefix/<libdir>/pkgconfig): main.cpp
#      compiled and linked with those flags alone, and run;
#   4. the installed capz CLI reads a PCD folder: it looks for the PCD module in
#      <prefix>/<libdir>/capz/ (relative to its bin/) before the build tree it was compiled in;
# Run as: cmake -DBUILD=<build dir> -DSOURCE=<repository> -DWORK=<scratch dir> -DCXX=<compiler>
#         [-DLAUNCHER=ccache] [-DPCD_FOLDER=<a small folder of .pcd frames>] -P run.cmake
cmake_minimum_required(VERSION 3.16)
foreach(v BUILD SOURCE WORK CXX)
  if(NOT ${v})
    message(FATAL_ERROR "run.cmake: -D${v}=... is needed")
  endif()
endforeach()

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (${rc}):\n${out}")
  endif()
  message(STATUS "${what}: ok")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/out)
set(prefix ${WORK}/prefix)

# 1. Install.
step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})
foreach(f include/capz/codec.h include/capz/tool/compress_file.h)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "install test: ${f} was not installed")
  endif()
endforeach()
file(GLOB_RECURSE config ${prefix}/*/capzConfig.cmake)
file(GLOB_RECURSE pcfile ${prefix}/*/capz.pc)
file(GLOB_RECURSE module ${prefix}/*/libcapz_pcl_io.so)
file(GLOB_RECURSE geom_module ${prefix}/*/libcapz_pcl_geom.so)
if(NOT config OR NOT pcfile OR NOT module OR NOT geom_module)
  message(FATAL_ERROR "install test: capzConfig.cmake, capz.pc, libcapz_pcl_io.so or "
                      "libcapz_pcl_geom.so missing "
                      "under ${prefix}")
endif()
get_filename_component(pcdir ${pcfile} DIRECTORY)

# 2. find_package(capz).
set(launcher "")
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
step("configure tests/consumer" ${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer -B ${WORK}/build
     -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX} ${launcher}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
step("build tests/consumer" ${CMAKE_COMMAND} --build ${WORK}/build -j2)
step("compress_take (capz::capz)" ${WORK}/build/compress_take ${WORK}/out)
message(STATUS "${step_output}")
step("decode_take (capz::decode)" ${WORK}/build/decode_take ${WORK}/out)
message(STATUS "${step_output}")

# 3. pkg-config.
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${pcdir})
step("pkg-config capz" ${PKG_CONFIG} --cflags --libs capz)
string(STRIP "${step_output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
step("c++ main.cpp $(pkg-config --cflags --libs capz)" ${CXX} -std=c++17 -O1
     ${SOURCE}/tests/consumer/main.cpp -o ${WORK}/pc_compress_take ${flags})
file(REMOVE_RECURSE ${WORK}/out)
file(MAKE_DIRECTORY ${WORK}/out)
step("pc_compress_take" ${WORK}/pc_compress_take ${WORK}/out)
step("decode_take on its output" ${WORK}/build/decode_take ${WORK}/out)

# 4. The installed CLI and its PCD module.
if(PCD_FOLDER AND EXISTS ${PCD_FOLDER})
  # capz reads binary PCD itself; ascii frames go through PCL, in the module. The dynamic
  # loader's trace names the module it opened: the installed one.
  file(REMOVE_RECURSE ${WORK}/ascii)
  step("installed capz convert to ascii PCD" ${prefix}/bin/capz convert ${PCD_FOLDER}
       ${WORK}/ascii/ --pcd-encoding ascii -q)
  step("installed capz info on an ascii PCD folder" ${CMAKE_COMMAND} -E env LD_DEBUG=files
       ${prefix}/bin/capz info ${WORK}/ascii)
  string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" prefix_re "${prefix}")
  if(NOT step_output MATCHES "file=${prefix_re}/[^ ]*/libcapz_pcl_io\\.so ")
    message(FATAL_ERROR "install test: the installed capz did not load ${module}:\n${step_output}")
  endif()
endif()
message(STATUS "install test: capz installed to ${prefix} builds and runs a consumer")
