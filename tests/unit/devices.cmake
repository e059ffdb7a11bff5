# Simulated devices and their adapters (src/devices, docs/devices.md).
skillcell_unit_test(test_device_world device_world_test.cpp)
target_link_libraries(test_device_world PRIVATE skillcell_world skillcell_test_support)

skillcell_unit_test(test_device_ur5 device_ur5_test.cpp)
target_link_libraries(test_device_ur5 PRIVATE skillcell_ur5 skillcell_test_support)

skillcell_unit_test(test_device_robotiq device_robotiq_test.cpp)
target_link_libraries(test_device_robotiq PRIVATE skillcell_robotiq skillcell_test_support
                                                  PkgConfig::MODBUS)

# The devices together: world model, UR5 and 2F-85, each on its own server.
skillcell_unit_test(test_device_cell device_cell_test.cpp)
target_link_libraries(test_device_cell PRIVATE skillcell_world skillcell_ur5 skillcell_robotiq
                                               skillcell_test_support)

skillcell_unit_test(test_device_schmalz device_schmalz_test.cpp)
target_link_libraries(test_device_schmalz PRIVATE skillcell_schmalz skillcell_test_support)

# The device components as processes (`skillcell device world|ur5|schmalz`).
skillcell_unit_test(test_device_processes device_process_test.cpp)
target_link_libraries(test_device_processes PRIVATE skillcell_world skillcell_skills
                                                    skillcell_test_support)
target_compile_definitions(test_device_processes PRIVATE SKILLCELL_BINARY="$<TARGET_FILE:skillcell>")
add_dependencies(test_device_processes skillcell)

# The gripper adapters' microcontroller boot profile (`--boot-profile tinyua`).
add_test(NAME cli.device_boot_profile
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/device_boot_profile.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.device_boot_profile PROPERTIES TIMEOUT 90)

# Two parallel-gripper models (2F-85, AG-95), one skill scenario; the AG-95's registers.
skillcell_unit_test(test_device_parallel_grippers device_parallel_grippers_test.cpp)
target_link_libraries(test_device_parallel_grippers PRIVATE skillcell_robotiq skillcell_dh
                                                            skillcell_test_support PkgConfig::MODBUS)

# Tests that run components as processes with discovery on: each case in a private network
# namespace (tests/netns/run_in_private_netns.sh as the "emulator"), see discovery.cmake.
function(skillcell_cell_test name)
  add_executable(${name} ${ARGN})
  target_link_libraries(${name} PRIVATE skillcell_world skillcell_skills skillcell_test_support
                                        GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE SKILLCELL_BINARY="$<TARGET_FILE:skillcell>")
  add_dependencies(${name} skillcell)
  set_target_properties(${name} PROPERTIES
    CROSSCOMPILING_EMULATOR ${PROJECT_SOURCE_DIR}/tests/netns/run_in_private_netns.sh)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 30 PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 240)
endfunction()

# The Kelvin tool changer: its tool table, and the changer in a cell.
skillcell_cell_test(test_device_toolchanger device_toolchanger_test.cpp)
target_link_libraries(test_device_toolchanger PRIVATE skillcell_toolchanger)

# The whole work cell: tool changes and two picks and places, checked in the world model.
skillcell_cell_test(test_device_work_cell device_work_cell_test.cpp)

# Grasp planning of the pick-and-place composite (pure geometry).
skillcell_unit_test(test_grasp_planner grasp_planner_test.cpp)
target_link_libraries(test_grasp_planner PRIVATE skillcell_pickplace)
