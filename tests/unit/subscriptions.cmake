# Subscriptions: the clock-free core (fake time) and the services over real sockets.
skillcell_unit_test(test_subscriptions
  subscription_core_test.cpp
  subscription_socket_test.cpp)
target_link_libraries(test_subscriptions PRIVATE skillcell_ua_subscriptions skillcell_test_support)
