# The skill layer: the state machine table, skills served by a component, the SkillClient.
skillcell_unit_test(test_skill_state_machine skill_state_machine_test.cpp)
target_link_libraries(test_skill_state_machine PRIVATE skillcell_skills)
