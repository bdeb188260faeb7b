// The pipeline's layers: the one list. Each line is one stage, in the order
// a tick runs them (docs/pipeline.md):
//   X(name, Enumerator, rig sections, document)
// name: the stage's functions in stages:: (name_compiled, _describe,
// _validate, _state_bytes, _init, _step, _flag_inputs; stage_fns.hpp
// declares them, the stage file stage_<name>.cpp defines them), its members
// of LayerSet and Pipeline (StageData, stage_<name>.hpp, included by
// stage_data.hpp), and its key in sinewd's [layers], in a recording's
// description and in the statistics.
// Enumerator: its Stage (stage.hpp). rig sections: the rig spec's sections
// that compile the layer (rigc), for messages about a layer the rig lacks.
// document: the one that describes it. The Stage enum, the stage functions'
// declarations, the stage table (stage_table.hpp) and the stages' members of
// LayerSet and Pipeline are expanded from it.
#pragma once

#define SINEW_STAGE_LIST(X)                                    \
  X(skinning, kSkinning, "", "docs/numerics.md")               \
  X(sph, kSph, "[[sph]]", "docs/sph.md")                       \
  X(metaballs, kMetaballs, "[metaballs]", "docs/metaballs.md") \
  X(barnet, kBarnet, "[[barnet]]", "docs/barnet.md")           \
  X(anatomy, kAnatomy, "[[muscle]] and [skin]", "docs/anatomy.md")
