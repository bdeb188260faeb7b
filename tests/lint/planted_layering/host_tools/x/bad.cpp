#include "firmware/daemon/config.hpp"  // planted: not a public header
#include "firmware/runtime/runtime.hpp"  // allowed
