# Compiler flags shared by every burrlab target: warnings as errors, optional sanitizers.
add_library(burrlab_options INTERFACE)
target_compile_options(burrlab_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Werror)
if(BURRLAB_SANITIZE)
  target_compile_options(burrlab_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(burrlab_options INTERFACE -fsanitize=address,undefined)
endif()
find_program(CCACHE_PROGRAM ccache)
if(CCACHE_PROGRAM)
  set(CMAKE_CXX_COMPILER_LAUNCHER "${CCACHE_PROGRAM}")
endif()

# burrlab_library(NAME SOURCES ... DEPS ...) declares burrlab::NAME with its public headers
# in <folder>/include and private sources in <folder>/src.
function(burrlab_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(burrlab_${name} STATIC ${ARG_SOURCES})
    target_include_directories(burrlab_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                               PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(burrlab_${name} PUBLIC ${ARG_PUBLIC_DEPS}
                                          PRIVATE burrlab_options ${ARG_PRIVATE_DEPS})
  else()
    add_library(burrlab_${name} INTERFACE)
    target_include_directories(burrlab_${name} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(burrlab_${name} INTERFACE ${ARG_PUBLIC_DEPS})
  endif()
  add_library(burrlab::${name} ALIAS burrlab_${name})
endfunction()
