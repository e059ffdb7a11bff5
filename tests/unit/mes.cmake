# unit tests of src/mes: the journal, process descriptions, step binding, skill facts.
# (The MES in the paper's work cell, every component a process, is in namespaces.cmake.)
# Orders on no-op skills of in-process servers: contention, parallel steps, priority, cancel;
# the connection pool that keeps the MES's sessions between steps.
skillcell_unit_test(test_mes_units
  mes/journal_test.cpp
  mes/process_description_test.cpp
  mes/step_binding_test.cpp
  mes/skill_facts_test.cpp
  mes/process_check_test.cpp
  mes/orders_test.cpp
  mes/skill_connection_pool_test.cpp)
target_link_libraries(test_mes_units PRIVATE skillcell_mes skillcell_cell skillcell_test_support)
target_compile_definitions(test_mes_units PRIVATE SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# `skillcell process check`: exit codes, FILE:LINE problems, the clean process's steps.
add_test(NAME cli.process_check
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/process_check_cli.sh $<TARGET_FILE:skillcell>
                 ${PROJECT_SOURCE_DIR})

# `skillcell mes` / `skillcell run` on bad input: exit codes and messages.
add_test(NAME cli.mes
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/mes_cli_test.sh $<TARGET_FILE:skillcell>)

# `skillcell demo` end to end: the whole cell, the process, world state, journal, table.
add_test(NAME cli.demo
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/demo_test.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.demo PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 960)

# The paper's second demonstrator: terminal blocks on a DIN rail, a cell file and a process
# the MES runs unchanged; world state and journal.
add_test(NAME cli.demo_din_rail
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/demo_din_rail_test.sh $<TARGET_FILE:skillcell>
                 ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.demo_din_rail PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 660)

# The paper's first demonstrator: fuses into a fuse box with the KUKA iiwa's force-limited
# insertion; world state and journal, and a slot out of tolerance stopping on the force limit.
foreach(mode aligned misaligned)
  add_test(NAME cli.demo_fuse_box_${mode}
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/demo_fuse_box_test.sh $<TARGET_FILE:skillcell>
                   ${PROJECT_SOURCE_DIR} ${mode})
  set_tests_properties(cli.demo_fuse_box_${mode} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 660)
endforeach()
