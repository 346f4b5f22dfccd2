# Warning flags and the embedded rules (no exceptions, no RTTI) for common/ and firmware/.
function(digitizer_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion)
endfunction()

function(digitizer_embedded target)
  digitizer_warnings(${target})
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()

# Under the sanitizers (a Debug build), a library whose code the long statistical tests run is
# optimised (-O2), still instrumented: at -O0 Eigen's small solvers and the basis loops run up to
# 60 times slower than in a release build (a curve's Monte Carlo test: 314 s against 5 s), and
# those tests decide how long the suites take.
# EXCEPT names files left at -O0 because optimising them costs minutes of compiling (Eigen's
# large solvers) for tests that take seconds. The fuzzing build keeps its own flags.
function(digitizer_optimise_under_sanitizers target)
  cmake_parse_arguments(O "" "" "EXCEPT" ${ARGN})
  if(NOT DIGITIZER_SANITIZE OR DIGITIZER_FUZZ)
    return()
  endif()
  target_compile_options(${target} PRIVATE $<$<CONFIG:Debug>:-O2>)
  if(O_EXCEPT)
    set_source_files_properties(${O_EXCEPT} PROPERTIES COMPILE_OPTIONS $<$<CONFIG:Debug>:-O0>)
  endif()
endfunction()
