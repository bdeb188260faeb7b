#include "hal/common/pose_frame.hpp"  // planted: sim_core must not see hal
