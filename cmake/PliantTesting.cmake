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
