// inhap studio server: a port in use (include/inhap/studio/server.hpp, listen_on).
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/server.hpp"

using namespace inhap::studio;

TEST(StudioServer, TheDefaultPortMovesOnWhenTakenAPortAskedForDoesNot) {
  const std::string token = make_token();
  const auto first = listen_on(0, false, ".", token);  // any free port
  const int taken = first->port();
  ASSERT_GT(taken, 0);
  // Taken: asked for explicitly, an error; as the default, the next free port after it.
  EXPECT_THROW(listen_on(taken, false, ".", token), inhap::Error);
  const auto second = listen_on(taken, true, ".", token);
  EXPECT_GT(second->port(), taken);
  EXPECT_LE(second->port(), taken + 20);
  // No free port among the tries: an error naming them.
  try {
    listen_on(taken, true, ".", token, 0);
    ADD_FAILURE() << "expected an error";
  } catch (const inhap::Error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(taken)), std::string::npos) << e.what();
  }
}
