// Every stage's data declarations (StageData, stage.hpp): one include per
// line of stage_list.hpp.
#pragma once

#include "stage_anatomy.hpp"
#include "stage_barnet.hpp"
#include "stage_metaballs.hpp"
#include "stage_skinning.hpp"
#include "stage_sph.hpp"
