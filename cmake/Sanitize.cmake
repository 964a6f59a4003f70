# Sanitizer and fuzzing builds (scripts/sanitize.sh configures one in build-sanitize with clang).
#
# HDRC_SANITIZE: AddressSanitizer and UndefinedBehaviorSanitizer on every target. UBSan's `vptr`
#   check needs the RTTI of the classes it checks, and Debian's glslang is built without it (its
#   typeinfo for glslang::TShader/TProgram does not exist, so the link fails): the files that use
#   glslang's classes are built with -fno-sanitize=vptr (hdrc_no_vptr_check below); every other
#   check stays on there too. Runtime options and the LeakSanitizer suppressions of third-party
#   leaks are in scripts/sanitize.sh and scripts/lsan.supp.
# HDRC_FUZZ (clang only): coverage instrumentation for libFuzzer on every target, and the
#   harnesses of fuzz/ with a bounded run of each under CTest (label `fuzz`).
option(HDRC_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(HDRC_FUZZ "Build the libFuzzer harnesses of fuzz/ (clang; use with HDRC_SANITIZE)" OFF)

if(HDRC_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

if(HDRC_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "HDRC_FUZZ needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ (scripts/sanitize.sh does)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# Source files that use glslang's classes (built without RTTI by Debian): no UBSan vptr check.
function(hdrc_no_vptr_check)
  if(HDRC_SANITIZE)
    set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
  endif()
endfunction()
