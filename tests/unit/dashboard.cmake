# src/dashboard: the events pushed to the pages (EventHub) and the view they come from
# (CellView), without a browser; tests/browser has the page in Chromium.
skillcell_unit_test(test_dashboard dashboard/dashboard_test.cpp)
find_package(nlohmann_json REQUIRED)
target_link_libraries(test_dashboard PRIVATE skillcell_dashboard nlohmann_json::nlohmann_json)
# The scene's subscription against a world model server on loopback.
skillcell_unit_test(test_scene_watcher dashboard/scene_watcher_test.cpp)
target_link_libraries(test_scene_watcher PRIVATE skillcell_dashboard skillcell_world
                                                 skillcell_test_support)
# The skills' states followed over one session per component, against a server on loopback.
skillcell_unit_test(test_skill_state_follower dashboard/skill_state_follower_test.cpp)
target_link_libraries(test_skill_state_follower PRIVATE skillcell_dashboard skillcell_test_support)
