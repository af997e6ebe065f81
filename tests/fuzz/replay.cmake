# Included from tests/CMakeLists.txt (the normal build, any compiler, no libFuzzer): each fuzz
# target is linked with replay_main.cpp into capz_fuzz_replay_<name>, and ctest replays its
# committed corpus as test fuzz_replay.<name> (label "fuzz"). replay_main.cpp is compiled once,
# as an object library, not once a target.
include(${CMAKE_CURRENT_LIST_DIR}/targets.cmake)
add_library(capz_fuzz_replay_main OBJECT ${CMAKE_CURRENT_LIST_DIR}/replay_main.cpp)
foreach(name ${CAPZ_FUZZ_TARGETS})
  set(exe capz_fuzz_replay_${name})
  add_executable(${exe} ${CMAKE_CURRENT_LIST_DIR}/fuzz_${name}.cpp
                        $<TARGET_OBJECTS:capz_fuzz_replay_main>)
  capz_fuzz_setup(${exe})
  add_test(NAME fuzz_replay.${name}
           COMMAND ${exe} ${CMAKE_CURRENT_LIST_DIR}/corpus/${name})
  set_tests_properties(fuzz_replay.${name} PROPERTIES LABELS fuzz TIMEOUT 600)
endforeach()
