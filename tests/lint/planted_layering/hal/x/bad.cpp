#include "firmware/runtime/runtime.hpp"  // planted
#include "sim_core/sph/sph_model.hpp"  // planted: physics in hal
