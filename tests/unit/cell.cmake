# src/cell: cell files read and checked; one input file per class of mistake in
# tests/data/cells/.
skillcell_unit_test(test_cell cell/cell_file_test.cpp cell/device_arguments_test.cpp)
target_link_libraries(test_cell PRIVATE skillcell_cell)
target_compile_definitions(test_cell PRIVATE SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_test(NAME cli.cell_check COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cell/cell_check_cli.sh
                                     $<TARGET_FILE:skillcell> ${PROJECT_SOURCE_DIR})
# `cell up`, `cell status`, `cell down`: a small cell in its own network namespace (root).
add_test(NAME cli.cell_up COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cell/cell_up_cli.sh
                                  $<TARGET_FILE:skillcell> ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.cell_up PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)
# The cell with two robots runs two branches of one process at once, each on its own robot.
add_test(NAME cli.two_robots COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cell/two_robots_cell.sh
                                     $<TARGET_FILE:skillcell> ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.two_robots PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)
