# Builds ezc3d (CAPZ_EZC3D_DIR) into this build tree as a static library target `ezc3d`.
# Only the interop tests link it (EXCLUDE_FROM_ALL keeps it out of other targets' builds, and
# out of `all` unless those tests are built). Its options are set as normal variables before
# add_subdirectory; CMP0077 NEW makes its option() calls honour them.
set(CMAKE_POLICY_DEFAULT_CMP0077 NEW)
set(BUILD_SHARED_LIBS OFF)
set(BUILD_TESTS OFF)
set(BUILD_EXAMPLE OFF)
set(BUILD_DOC OFF)
set(GET_OFFICIAL_DOCUMENTATION OFF)
set(BINDER_PYTHON3 OFF)
set(BINDER_MATLAB OFF)
set(BINDER_OCTAVE OFF)
add_subdirectory(${CAPZ_EZC3D_DIR} ${CMAKE_CURRENT_BINARY_DIR}/ezc3d EXCLUDE_FROM_ALL)
unset(CMAKE_POLICY_DEFAULT_CMP0077)
unset(BUILD_SHARED_LIBS)

# Not our code: no warnings from its sources (-w after -Wall -Wextra wins), and its headers
# included as system headers so they add none to the tests either.
target_compile_options(ezc3d PRIVATE -w)
get_target_property(_capz_ezc3d_inc ezc3d INTERFACE_INCLUDE_DIRECTORIES)
set_target_properties(ezc3d PROPERTIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${_capz_ezc3d_inc}")
message(STATUS "ezc3d from ${CAPZ_EZC3D_DIR}: interop tests enabled")
