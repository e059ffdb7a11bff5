# src/process: ChildProcess, which starts the children of our components (the KB's engines,
# the demo's components, the tool changer's tool adapters).
skillcell_unit_test(test_process process/child_process_test.cpp process/cpu_time_test.cpp)
target_include_directories(test_process PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
target_link_libraries(test_process PRIVATE skillcell_process)
