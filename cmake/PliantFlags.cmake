# Warning-free C11 with gcc: -Wall -Wextra -Werror everywhere we compile C.
set(PLIANT_C_WARNINGS -Wall -Wextra -Werror -Wno-unused-parameter)
add_compile_options("$<$<COMPILE_LANGUAGE:C>:${PLIANT_C_WARNINGS}>")
# _GNU_SOURCE for strdup/dladdr/clock_gettime while keeping -std=c11.
add_compile_definitions(_GNU_SOURCE)
if(PLIANT_SANITIZE)
  add_compile_options("$<$<COMPILE_LANGUAGE:C>:-fsanitize=address,undefined;-fno-omit-frame-pointer;-fno-sanitize-recover=undefined>")
  add_link_options(-fsanitize=address,undefined)
endif()
