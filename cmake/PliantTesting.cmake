# Tests do not depend on the machine: every test of a folder that is not
# labelled "gpu" runs with PLIANT_DEVICE=cpu, so that on a machine with a GPU
# the loader adds no implicit CudaDevice and the CPU path (the reference the
# thresholds were set on) runs, as in CI.  The gpu-labelled tests compare the
# two paths explicitly (ctest -L gpu).  Called at the end of each folder
# (deferred by pliant_pin_tests_to_cpu; pliant_add_test calls it).
function(pliant_pin_device_cpu_now)
  get_property(tests DIRECTORY PROPERTY TESTS)
  foreach(t ${tests})
    get_test_property(${t} LABELS labels)
    if(NOT labels OR NOT "gpu" IN_LIST labels)
      set_property(TEST ${t} APPEND PROPERTY ENVIRONMENT "PLIANT_DEVICE=cpu")
    endif()
  endforeach()
endfunction()

function(pliant_pin_tests_to_cpu)
  get_property(pinned DIRECTORY PROPERTY PLIANT_DEVICE_PINNED)
  if(NOT pinned)
    set_property(DIRECTORY PROPERTY PLIANT_DEVICE_PINNED 1)
    cmake_language(DEFER CALL pliant_pin_device_cpu_now)
  endif()
endfunction()

# pliant_add_test(NAME SOURCES a.c ... [LIBS lib ...] [TIMEOUT s])
# A Check test executable registered with ctest.  Tests see:
#   PL_SOURCE_DIR  the source tree (scenes, meshes)
#   PL_BINARY_DIR  the build tree (plugins, bin)
function(pliant_add_test name)
  cmake_parse_arguments(T "" "TIMEOUT" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE PkgConfig::CHECK ${T_LIBS} m)
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR}/tests) # test_tmp.h
  target_compile_definitions(${name} PRIVATE
    PL_SOURCE_DIR="${CMAKE_SOURCE_DIR}" PL_BINARY_DIR="${CMAKE_BINARY_DIR}")
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  add_test(NAME ${name} COMMAND ${name})
  pliant_pin_tests_to_cpu()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  # Timeouts are set for the optimised build.  The sanitiser build is Debug
  # (-O0) with ASan and UBSan, 6-9 times slower (test_cable_scene's finger:
  # 12 s of stepping become 100 s), so its Check and ctest timeouts scale by 3:
  # a hang is still caught, a loaded CI machine no longer times out.
  set(mult 1)
  if(PLIANT_SANITIZE)
    set(mult 3)
  endif()
  math(EXPR T_TIMEOUT "${T_TIMEOUT} * ${mult}")
  # CK_FORK=yes: a crashing test is reported, not fatal to the suite.
  set_tests_properties(${name} PROPERTIES TIMEOUT ${T_TIMEOUT}
    ENVIRONMENT "CK_FORK=yes;CK_VERBOSITY=normal;CK_TIMEOUT_MULTIPLIER=${mult};OMP_NUM_THREADS=2;OMP_WAIT_POLICY=PASSIVE")
endfunction()

# pliant_add_plugin(NAME SOURCES a.c ... [LIBS lib ...] [NOINSTALL])
# A run-time loaded plugin: build/plugins/libpliant_<NAME>.so, found by
# <RequiredPlugin name="NAME"/>.  It links libpliant for the SDK functions
# and nothing else of it (--no-undefined: a call to a function the SDK does
# not declare fails at link time, as it would out of the tree).  NOINSTALL:
# not part of the installed SDK (the tutorial plugin).
function(pliant_add_plugin name)
  cmake_parse_arguments(P "NOINSTALL" "" "SOURCES;LIBS" ${ARGN})
  add_library(${name} MODULE ${P_SOURCES})
  target_link_libraries(${name} PRIVATE pliant ${P_LIBS})
  target_link_options(${name} PRIVATE -Wl,--no-undefined)
  set_target_properties(${name} PROPERTIES
    OUTPUT_NAME pliant_${name}
    LIBRARY_OUTPUT_DIRECTORY ${PLIANT_PLUGIN_OUTPUT_DIR}
    C_VISIBILITY_PRESET hidden)
  if(NOT P_NOINSTALL)
    install(TARGETS ${name} LIBRARY DESTINATION lib/pliant/plugins)
  endif()
endfunction()
