# unit tests of src/mes: the journal, process descriptions, step binding, skill facts.
skillcell_unit_test(test_mes_journal mes/journal_test.cpp)
target_link_libraries(test_mes_journal PRIVATE skillcell_mes skillcell_test_support)
skillcell_unit_test(test_mes_process_description mes/process_description_test.cpp)
target_link_libraries(test_mes_process_description PRIVATE skillcell_mes)
skillcell_unit_test(test_mes_step_binding mes/step_binding_test.cpp)
target_link_libraries(test_mes_step_binding PRIVATE skillcell_mes)
skillcell_unit_test(test_mes_skill_facts mes/skill_facts_test.cpp)
target_link_libraries(test_mes_skill_facts PRIVATE skillcell_mes)

# The MES in the paper's work cell, every component a process (private network namespace).
skillcell_cell_test(test_mes_cell mes/mes_cell_test.cpp)
target_link_libraries(test_mes_cell PRIVATE skillcell_mes)

# `skillcell mes` / `skillcell run` on bad input: exit codes and messages.
add_test(NAME cli.mes
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/mes_cli_test.sh $<TARGET_FILE:skillcell>)

# `skillcell demo` end to end: the whole cell, the process, world state, journal, table.
add_test(NAME cli.demo
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mes/demo_test.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.demo PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 960)
