include(CMakePackageConfigHelpers)

get_property(_targets GLOBAL PROPERTY VLPGROUND_INSTALL_TARGETS)
install(TARGETS ${_targets} EXPORT vlpgroundTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT vlpgroundTargets NAMESPACE vlpground::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vlpground)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/vlpgroundConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/vlpgroundConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vlpground)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/vlpgroundConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/vlpgroundConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/vlpgroundConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vlpground)
