#include "tests/x/helper.hpp"  // planted: a tool includes a test file
