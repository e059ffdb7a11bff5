# Tests whose every case runs in a private network namespace of its own
# (tests/netns/run_in_private_netns.sh as the test "emulator"), so that nothing they multicast
# reaches a real network:
# - the mDNS responder, watcher and registrar on real multicast;
# - components as processes with discovery on:
#   - the Kelvin tool changer: its tool table, and the changer in a cell;
#   - the whole work cell: tool changes and two picks and places, checked in the world model;
#   - terminal blocks placed on a DIN rail by the PlaceTerminalBlock composite;
#   - fuses inserted into a fuse box by the InsertFuse composite, and its refusals;
#   - the knowledge-base component: discovery, recording, models, kills;
#   - the MES in the paper's work cell.
add_executable(test_in_namespaces
  mdns_test.cpp
  device_toolchanger_test.cpp
  device_work_cell_test.cpp
  device_din_rail_cell_test.cpp
  device_fuse_box_cell_test.cpp
  kb/kb_component_test.cpp
  mes/mes_cell_test.cpp)
target_link_libraries(test_in_namespaces PRIVATE skillcell_ua_discovery skillcell_world
  skillcell_skills skillcell_toolchanger skillcell_http skillcell_mes skillcell_cell
  skillcell_test_support
  GTest::gtest_main)
target_compile_definitions(test_in_namespaces PRIVATE
  SKILLCELL_BINARY="$<TARGET_FILE:skillcell>" SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_dependencies(test_in_namespaces skillcell)
set_target_properties(test_in_namespaces PROPERTIES
  CROSSCOMPILING_EMULATOR ${PROJECT_SOURCE_DIR}/tests/netns/run_in_private_netns.sh)
gtest_discover_tests(test_in_namespaces DISCOVERY_TIMEOUT 30
                     PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 240 COST 20)
