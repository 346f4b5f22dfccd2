# Warning flags and the embedded rules (no exceptions, no RTTI) for common/ and firmware/.
function(digitizer_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion)
endfunction()

function(digitizer_embedded target)
  digitizer_warnings(${target})
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()
