#include "host_tools/rigc/rig_spec.hpp"  // planted: the board links no host code
