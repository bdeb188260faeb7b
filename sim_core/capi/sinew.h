/* sinew's deterministic core from C (and any language with a C FFI): load a
 * compiled rig blob (.rig, written by rigc) and step its pipeline. Box2D
 * v3's box2d.h is the model: plain structs and opaque handles, and every
 * byte of memory is the caller's. Nothing here allocates, reads a clock,
 * takes a lock or calls the OS; the same inputs give the same output words
 * on every platform sinew supports (docs/embedding.md).
 *
 * Memory: each handle lives at the start of a block the caller provides,
 * 8-byte aligned, of the size the matching *_bytes function reports; a
 * handle is valid while its block is, and needs no release. A blob must be
 * 8-byte aligned (the C allocator's blocks are) and may be released once
 * loaded.
 *
 * Units: inputs are the rig's DOF values in its input order, then its
 * external inputs: a rotational DOF as a binary angle (2^32 = one turn,
 * read as int32), a translational one in Q12.20 rig units (one unit = 2^20);
 * external inputs in the units the rig spec declares. Vertex positions are
 * Q12.20 rig units. */
#ifndef SINEW_H
#define SINEW_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SINEW_C_API_VERSION 1

/* 0: success; otherwise the operation failed and `message` names what was
 * refused (the section and field of a blob, the stage of a step). */
typedef struct sinew_status {
  int32_t code;
  char message[192];
} sinew_status;

enum {
  SINEW_OK = 0,
  SINEW_ERROR_ARGUMENT = 1, /* a null pointer, a misaligned or too small block */
  SINEW_ERROR_BLOB = 2,     /* the blob or one of its layer sections was refused */
  SINEW_ERROR_INIT = 3,     /* the pipeline refused its options or a layer its model */
  SINEW_ERROR_STEP = 4      /* a step failed; the message names the stage */
};

typedef struct sinew_rig sinew_rig;
typedef struct sinew_pipeline sinew_pipeline;

typedef struct sinew_rig_info {
  uint32_t joint_count;
  uint32_t input_count;          /* the rig's DOF inputs */
  uint32_t external_input_count; /* inputs the layers read (forces, pressures) */
  uint32_t vertex_count;
  uint32_t layer_count; /* stages beyond skinning the blob carries (after sinew_layers_load) */
} sinew_rig_info;

/* The rig (skeleton, skin, limits) of a blob, without its layer sections. */
sinew_status sinew_rig_bytes(const void* blob, size_t blob_bytes, size_t* bytes);
sinew_status sinew_rig_load(const void* blob, size_t blob_bytes, void* memory, size_t bytes, sinew_rig** out);
/* The blob's layer sections (SPH joints, metaballs, bar-nets, muscles and
 * skin), for a rig loaded from the same blob. A blob without layers needs 0
 * bytes (memory may then be null). Call before sinew_pipeline_init. */
sinew_status sinew_layers_bytes(const sinew_rig* rig, const void* blob, size_t blob_bytes, size_t* bytes);
sinew_status sinew_layers_load(sinew_rig* rig, const void* blob, size_t blob_bytes, void* memory, size_t bytes);
sinew_rig_info sinew_rig_get_info(const sinew_rig* rig);

/* The stages of a tick, in order (skinning first; docs/pipeline.md). */
uint32_t sinew_stage_count(void);
const char* sinew_stage_name(uint32_t stage); /* null past the last */

typedef struct sinew_pipeline_options {
  uint32_t tick_hz;    /* 0: the rate the rig's layers were compiled for */
  uint32_t stages_off; /* bit i switches stage i off (skinning always runs); 0: every stage the rig carries */
} sinew_pipeline_options;

/* options may be null (the defaults above). 0 when the rig is null. */
size_t sinew_pipeline_state_bytes(const sinew_rig* rig, const sinew_pipeline_options* options);
sinew_status sinew_pipeline_init(const sinew_rig* rig, const sinew_pipeline_options* options, void* memory,
                                 size_t bytes, sinew_pipeline** out);
/* One tick. inputs: input_count then external_input_count values; fewer is
 * refused. On failure the pose is what the stages before the failing one
 * made (docs/pipeline.md, the error rule). */
sinew_status sinew_pipeline_step(sinew_pipeline* pipeline, const int32_t* inputs, size_t input_count);

typedef struct sinew_vertices {
  const int32_t* x; /* Q12.20 rig units, vertex_count each */
  const int32_t* y;
  const int32_t* z;
  uint32_t count;
} sinew_vertices;

/* The deformed skin after the last step (the rest pose before the first);
 * the arrays stay valid and are rewritten by each step. */
sinew_vertices sinew_pipeline_vertices(const sinew_pipeline* pipeline);

#ifdef __cplusplus
}
#endif

#endif /* SINEW_H */
