# Project-wide warnings and sanitizers, applied to our targets through gt_set_warnings().
function(gt_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wno-missing-field-initializers)
  if(GT_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

if(GT_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
