# The capz CLI does not link PCL (src/io/pcd_backend.h, src/codec/pcl_geom.h): PCL's libraries
# are loaded from capz's modules only when a PCD file goes through PCL or pdct / ts run.
#   cmake -DREADELF=readelf -DCLI=path/to/capz -P check_no_pcl.cmake
execute_process(COMMAND ${READELF} -d ${CLI} OUTPUT_VARIABLE out ERROR_VARIABLE err
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT out MATCHES "\\(NEEDED\\)")
  message(FATAL_ERROR "no-pcl check: readelf -d ${CLI} failed (${rc}): ${err}")
endif()
string(REGEX MATCHALL "Shared library: \\[[^]]*\\]" needed "${out}")
foreach(lib ${needed})
  if(lib MATCHES "libpcl|libflann|libvtk")
    message(FATAL_ERROR "no-pcl check: ${CLI} links ${lib}; PCL belongs in capz's modules")
  endif()
endforeach()
message(STATUS "no-pcl check: ${CLI} needs ${needed}")
