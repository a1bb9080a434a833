# Project-wide warnings and sanitizers, applied to our targets through gt_set_warnings().
function(gt_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wno-missing-field-initializers)
  if(GT_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Undefined behaviour stops the program (and fails its test) instead of printing and going on:
# a report nobody reads is no check.
if(GT_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined -fno-sanitize-recover=all)
endif()

# libFuzzer: every library is compiled with its coverage instrumentation so the fuzz targets
# (tests/fuzz) are guided through engine and eyetrack code; only the targets link its main.
if(GT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "GT_FUZZ needs clang (libFuzzer); use the asan preset or set "
                        "CMAKE_CXX_COMPILER=clang++")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
