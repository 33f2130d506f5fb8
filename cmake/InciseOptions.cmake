# Compile options every incise target gets: warnings, optional sanitizers, optional -march=native.
# Use: incise_target_options(<target>).

if(INCISE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

function(incise_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  # No silent fusing of a*b+c: whether GCC fuses depends on the inlining context, which would make the
  # same point evaluate to different bits on different paths. Eigen's explicit FMA kernels still apply.
  target_compile_options(${target} PRIVATE -ffp-contract=off)
  if(INCISE_NATIVE AND NOT INCISE_SANITIZE)
    # AVX-512 is left off: GCC 12 warns falsely inside Eigen's 512-bit kernels, and the 256-bit
    # kernels are as fast for 3-vectors.
    target_compile_options(${target} PRIVATE -march=native -mno-avx512f)
  endif()
endfunction()
