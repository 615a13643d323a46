# Strict warnings, as errors, on the project's own targets only.
function(vlpground_set_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror)
endfunction()

# A library of the project: strict warnings, namespaced alias, public include directory.
function(vlpground_library name)
  cmake_parse_arguments(ARG "" "INCLUDE_DIR" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(vlpground_${name} ${ARG_SOURCES})
  add_library(vlpground::${name} ALIAS vlpground_${name})
  set_target_properties(vlpground_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME vlpground_${name})
  target_include_directories(vlpground_${name} PUBLIC
    $<BUILD_INTERFACE:${ARG_INCLUDE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(vlpground_${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  vlpground_set_warnings(vlpground_${name})
  set_property(GLOBAL APPEND PROPERTY VLPGROUND_INSTALL_TARGETS vlpground_${name})
  install(DIRECTORY ${ARG_INCLUDE_DIR}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
