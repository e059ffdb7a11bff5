# The SkillDetector and the RemoteSkillBrowser against skill servers on loopback (no multicast:
# the tests feed the detector's "appeared"/"gone" themselves). The "tsan" preset builds it with
# ThreadSanitizer: cmake --preset tsan && cmake --build --preset tsan && ctest --preset tsan.
skillcell_unit_test(test_skill_detector skill_detector_test.cpp)
target_link_libraries(test_skill_detector PRIVATE skillcell_skills skillcell_test_support)
