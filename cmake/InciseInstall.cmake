# `cmake --install` produces a CMake package: find_package(incise CONFIG REQUIRED) then
# target_link_libraries(app PRIVATE incise::cutting).
include(CMakePackageConfigHelpers)

set(INCISE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/incise)
install(EXPORT inciseTargets NAMESPACE incise:: DESTINATION ${INCISE_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/inciseConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/inciseConfig.cmake INSTALL_DESTINATION ${INCISE_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/inciseConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/inciseConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/inciseConfigVersion.cmake
        DESTINATION ${INCISE_CMAKE_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/incise)
