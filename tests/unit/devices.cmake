# Simulated devices and their adapters (src/devices, docs/devices.md): the world model, the
# UR5, the 2F-85 and its Modbus registers, the devices together (each on its own server),
# the Schmalz vacuum gripper, the device components as processes (`skillcell device
# world|ur5|schmalz`), two parallel-gripper models (2F-85, AG-95) in one skill scenario, and
# the grasp planning of the pick-and-place composite (pure geometry).
skillcell_unit_test(test_devices
  device_world_test.cpp
  device_din_rail_test.cpp
  device_fuse_slot_test.cpp
  device_arm_test.cpp
  device_robotiq_test.cpp
  device_cell_test.cpp
  device_schmalz_test.cpp
  device_process_test.cpp
  device_parallel_grippers_test.cpp
  grasp_planner_test.cpp
  device_fuse_planner_test.cpp)
target_link_libraries(test_devices PRIVATE skillcell_world skillcell_arm skillcell_robotiq
  skillcell_schmalz skillcell_dh skillcell_skills skillcell_pickplace skillcell_test_support
  PkgConfig::MODBUS)
target_compile_definitions(test_devices PRIVATE SKILLCELL_BINARY="$<TARGET_FILE:skillcell>")
add_dependencies(test_devices skillcell)

# The world model's command line on a bad scene (fuse slots, their misalignment).
add_test(NAME cli.device_world_scene
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/device_world_scene_cli.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.device_world_scene PROPERTIES TIMEOUT 120)

# The gripper adapters' microcontroller boot profile (`--boot-profile tinyua`).
add_test(NAME cli.device_boot_profile
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/device_boot_profile.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.device_boot_profile PROPERTIES TIMEOUT 90)
