# Tests that run components as processes with discovery on, each case in a private network
# namespace (tests/netns/run_in_private_netns.sh as the "emulator", see discovery.cmake):
# - the Kelvin tool changer: its tool table, and the changer in a cell;
# - the whole work cell: tool changes and two picks and places, checked in the world model;
# - the knowledge-base component: discovery, recording, models, kills;
# - the MES in the paper's work cell.
add_executable(test_cells
  device_toolchanger_test.cpp
  device_work_cell_test.cpp
  kb/kb_component_test.cpp
  mes/mes_cell_test.cpp)
target_link_libraries(test_cells PRIVATE skillcell_world skillcell_skills skillcell_toolchanger
  skillcell_kb_http skillcell_mes skillcell_test_support GTest::gtest_main)
target_compile_definitions(test_cells PRIVATE
  SKILLCELL_BINARY="$<TARGET_FILE:skillcell>" SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_dependencies(test_cells skillcell)
set_target_properties(test_cells PROPERTIES
  CROSSCOMPILING_EMULATOR ${PROJECT_SOURCE_DIR}/tests/netns/run_in_private_netns.sh)
gtest_discover_tests(test_cells DISCOVERY_TIMEOUT 30 PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 240)
