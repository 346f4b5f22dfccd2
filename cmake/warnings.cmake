# Warning flags and the embedded rules (no exceptions, no RTTI) for common/ and firmware/.
function(digitizer_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion)
endfunction()

function(digitizer_embedded target)
  digitizer_warnings(${target})
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()

# Under the sanitizers (the asan and fuzz builds, both Debug), a library whose code the long
# statistical tests run is optimised (-O2), still instrumented: at -O0 Eigen's small solvers and
# the basis loops ran 63 times slower than in a release build (a curve's Monte Carlo test: 314 s
# against 5 s), and those tests decide how long the suites take. The fuzzer of the stages after
# parsing runs the same filters and fits, and gets through more inputs in its seconds.
# EXCEPT names files left at -O0 because optimising them costs more compiling (Eigen's large
# solvers) than their tests would gain. Their -O0 is appended to the file's own options.
function(digitizer_optimise_under_sanitizers target)
  cmake_parse_arguments(O "" "" "EXCEPT" ${ARGN})
  if(NOT DIGITIZER_SANITIZE)
    return()
  endif()
  target_compile_options(${target} PRIVATE $<$<CONFIG:Debug>:-O2>)
  if(O_EXCEPT)
    set_property(SOURCE ${O_EXCEPT} APPEND PROPERTY COMPILE_OPTIONS $<$<CONFIG:Debug>:-O0>)
  endif()
endfunction()
