# Warning-free C11 with gcc: -Wall -Wextra everywhere we compile C.
# -Werror only where the project asks for it (make test, CI: PLIANT_WERROR=ON),
# so that a newer compiler's new warning never stops a user's build.
option(PLIANT_WERROR "Turn C warnings into errors (make test and CI set it)" OFF)
set(PLIANT_C_WARNINGS -Wall -Wextra -Wno-unused-parameter)
if(PLIANT_WERROR)
  list(APPEND PLIANT_C_WARNINGS -Werror)
endif()
add_compile_options("$<$<COMPILE_LANGUAGE:C>:${PLIANT_C_WARNINGS}>")
# _GNU_SOURCE for strdup/dladdr/clock_gettime while keeping -std=c11.
add_compile_definitions(_GNU_SOURCE)
if(PLIANT_SANITIZE)
  add_compile_options("$<$<COMPILE_LANGUAGE:C>:-fsanitize=address,undefined;-fno-omit-frame-pointer;-fno-sanitize-recover=undefined>")
  add_link_options(-fsanitize=address,undefined)
endif()
# Fuzzing (tests/fuzz, make fuzz): clang only; every object is instrumented
# for libFuzzer's coverage feedback and checked by ASan and UBSan.
if(PLIANT_FUZZ OR PLIANT_FUZZ_COVERAGE)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PLIANT_FUZZ needs clang: configure with CC=clang (make fuzz does)")
  endif()
endif()
if(PLIANT_FUZZ)
  add_compile_options("$<$<COMPILE_LANGUAGE:C>:-fsanitize=fuzzer-no-link,address,undefined;-fno-omit-frame-pointer;-fno-sanitize-recover=undefined>")
  add_link_options(-fsanitize=address,undefined)
endif()
if(PLIANT_FUZZ_COVERAGE)
  add_compile_options("$<$<COMPILE_LANGUAGE:C>:-fprofile-instr-generate;-fcoverage-mapping>")
  add_link_options(-fprofile-instr-generate)
endif()
