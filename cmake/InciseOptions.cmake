# Compile options every incise target gets: warnings, optional sanitizers, optional -march=native.
# Use: incise_target_options(<target>).

option(INCISE_TSAN "Build with ThreadSanitizer (the threaded sim tests run under it)" OFF)
if(INCISE_SANITIZE AND INCISE_TSAN)
  message(FATAL_ERROR "INCISE_SANITIZE and INCISE_TSAN cannot be combined")
endif()
if(INCISE_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

if(INCISE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Fuzzing (tests/fuzz/): every library gets libFuzzer's coverage instrumentation; the harnesses link the
# fuzzer's main (-fsanitize=fuzzer). Needs clang and the sanitizers (INCISE_SANITIZE).
if(INCISE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "INCISE_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++-14), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  if(NOT INCISE_SANITIZE)
    message(FATAL_ERROR "INCISE_FUZZ needs INCISE_SANITIZE=ON (the harnesses run under ASan + UBSan)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

function(incise_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  # No silent fusing of a*b+c: whether GCC fuses depends on the inlining context, which would make the
  # same point evaluate to different bits on different paths. Eigen's explicit FMA kernels still apply.
  target_compile_options(${target} PRIVATE -ffp-contract=off)
  # Position-independent code (CMAKE_POSITION_INDEPENDENT_CODE) without GCC's assumption that a global
  # function may be replaced at load time: calls within incise stay direct and inlinable, as in -fPIE.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -fno-semantic-interposition)
  endif()
  if(INCISE_NATIVE AND NOT INCISE_SANITIZE AND NOT INCISE_TSAN)
    # AVX-512 is left off: GCC 12 warns falsely inside Eigen's 512-bit kernels, and the 256-bit
    # kernels are as fast for 3-vectors.
    target_compile_options(${target} PRIVATE -march=native -mno-avx512f)
  endif()
endfunction()

# incise_add_module(<name> SOURCES <files...> [PUBLIC <deps...>] [PRIVATE <deps...>])
# One folder = one library target `incise_<name>` = alias `incise::<name>`, public headers under
# <folder>/include, installed and exported in the incise package. PRIVATE dependencies stay out of the
# installed link interface (they are used in .cpp files only).
function(incise_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  set(target incise_${name})
  add_library(${target} ${ARG_SOURCES})
  add_library(incise::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC})
  foreach(dependency IN LISTS ARG_PRIVATE)
    target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:${dependency}>)
  endforeach()
  target_compile_features(${target} PUBLIC cxx_std_20)
  incise_target_options(${target})
  # A native build's public types hold Eigen values laid out for this CPU's vectors (AVX: 32-byte
  # alignment), so code that shares them (a user of the installed package) is compiled for the same CPU;
  # a program built without them crashes on a misaligned Eigen member. -DINCISE_NATIVE=OFF for a package
  # that other CPUs and other flags can use.
  if(INCISE_NATIVE AND NOT INCISE_SANITIZE AND NOT INCISE_TSAN)
    target_compile_options(${target} INTERFACE -march=native -mno-avx512f)
  endif()
  install(TARGETS ${target} EXPORT inciseTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
