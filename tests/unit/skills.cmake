# The skill layer: the state machine table, skills served by a component, the SkillClient.
skillcell_unit_test(test_skill_state_machine skill_state_machine_test.cpp)
target_link_libraries(test_skill_state_machine PRIVATE skillcell_skills)

skillcell_unit_test(test_skill skill_test.cpp)
target_link_libraries(test_skill PRIVATE skillcell_skills skillcell_test_support)

skillcell_unit_test(test_skill_client skill_client_test.cpp)
target_link_libraries(test_skill_client PRIVATE skillcell_skills skillcell_test_support)
# One test starts a real `skillcell server` process and kills it mid-run.
target_compile_definitions(test_skill_client PRIVATE SKILLCELL_BINARY="$<TARGET_FILE:skillcell>")
add_dependencies(test_skill_client skillcell)

# The example of a new skill type (examples/dispense_skill) keeps working.
skillcell_unit_test(test_example_dispense example_dispense_test.cpp)
target_include_directories(test_example_dispense PRIVATE ${PROJECT_SOURCE_DIR}/examples/dispense_skill)
target_link_libraries(test_example_dispense PRIVATE skillcell_skills skillcell_test_support)
target_compile_definitions(test_example_dispense PRIVATE
  SKILLCELL_EXAMPLE_MODEL="${PROJECT_SOURCE_DIR}/examples/dispense_skill/Example.DispenseSkill.NodeSet2.xml")
