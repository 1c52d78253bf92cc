# `cmake --install` puts the programs in bin/ and the participant SDK for C++
# (the libraries a node is made of, their headers, and a package
# configuration) where another CMake project finds it with
#   find_package(railcosim REQUIRED)
#   target_link_libraries(my_participant PRIVATE railcosim::node)
# (docs/participant-guide-cpp.md).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Folders 0755 whatever the installing user's umask (under umask 000 they
# were world-writable: anyone could plant a scene or an SDK module there);
# install(DIRECTORY) below says the same for the folders it copies.
set(CMAKE_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
set(railcosim_dir_permissions DIRECTORY_PERMISSIONS ${CMAKE_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS})

set_target_properties(railcosim_common PROPERTIES EXPORT_NAME common)
set_target_properties(railcosim_protocol PROPERTIES EXPORT_NAME protocol)
set_target_properties(railcosim_node PROPERTIES EXPORT_NAME node)
set_target_properties(railcosim_warnings PROPERTIES EXPORT_NAME warnings)

install(TARGETS master vehicle_node track_node soil_node fmu_node RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS railcosim_common railcosim_protocol railcosim_node railcosim_warnings
        EXPORT railcosimTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})

file(GLOB railcosim_sdk_headers ${PROJECT_SOURCE_DIR}/common/*.hpp
     ${PROJECT_SOURCE_DIR}/protocol/*.hpp ${PROJECT_SOURCE_DIR}/node/*.hpp)
# The node's own internals: the server's connections and the peer
# handshake, which no public header includes (tests/cpp_sdk_test.sh checks
# that every installed header's includes are installed).
list(REMOVE_ITEM railcosim_sdk_headers ${PROJECT_SOURCE_DIR}/node/server_conn.hpp
     ${PROJECT_SOURCE_DIR}/node/frame_source.hpp ${PROJECT_SOURCE_DIR}/node/peer_handshake.hpp)
install(FILES ${railcosim_sdk_headers} ${PROJECT_BINARY_DIR}/protocol/railcosim.pb.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/railcosim)
install(FILES ${PROJECT_SOURCE_DIR}/protocol/railcosim.proto
        DESTINATION ${CMAKE_INSTALL_DATADIR}/railcosim)
# What the C++ participant guide's checks use besides the programs: the
# scenes, and the worked example (a participant built against this package).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/railcosim/scenes
        ${railcosim_dir_permissions} FILES_MATCHING PATTERN "*.toml")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/cpp_soil/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/railcosim/examples/cpp_soil ${railcosim_dir_permissions})
# The Python SDK and its example, so that a Python participant needs nothing
# but the package either: the SDK finds the schema installed above.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/python/railcosim_sdk/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/railcosim/sdk/python/railcosim_sdk
        ${railcosim_dir_permissions} FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/examples/python_soil/soil_participant.py
              ${PROJECT_SOURCE_DIR}/examples/python_soil/README.md
        DESTINATION ${CMAKE_INSTALL_DATADIR}/railcosim/examples/python_soil)

set(railcosim_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/railcosim)
install(EXPORT railcosimTargets NAMESPACE railcosim:: DESTINATION ${railcosim_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/railcosimConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/railcosimConfig.cmake
                              INSTALL_DESTINATION ${railcosim_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/railcosimConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/railcosimConfig.cmake
              ${PROJECT_BINARY_DIR}/railcosimConfigVersion.cmake
        DESTINATION ${railcosim_cmake_dir})
