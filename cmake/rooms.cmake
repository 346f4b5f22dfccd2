# Include roots per library: a library sees the headers of its own folder and of the libraries it
# links, and no others, so an include that breaks the layering fails to compile instead of passing
# until a script greps for it. Headers keep their full paths ("host/fit/x.h"): each library's root
# is a folder in the build tree holding one symbolic link to its source folder.
function(digitizer_room target)
  set(root ${CMAKE_BINARY_DIR}/rooms/${target})
  foreach(dir ${ARGN})
    get_filename_component(parent ${root}/${dir} DIRECTORY)
    file(MAKE_DIRECTORY ${parent})
    if(NOT EXISTS ${root}/${dir})
      file(CREATE_LINK ${CMAKE_SOURCE_DIR}/${dir} ${root}/${dir} SYMBOLIC)
    endif()
  endforeach()
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    target_include_directories(${target} INTERFACE ${root})
  else()
    target_include_directories(${target} PUBLIC ${root})
  endif()
endfunction()
