/* A C program embedding sinew's core through sinew.h, as a user's would:
 * load a compiled rig, step it 200 ticks with its first input swept, and
 * print a checksum of the final vertices. Exit 0 when every call succeeds
 * and the skin moved; the checksum lets the test compare it with the C++
 * consumer's. Usage: consumer rig.rig */
#include <sinew/sinew.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void* aligned_block(size_t bytes) { return calloc(bytes / 8 + 1, 8); }

static int fail(const char* what, const sinew_status* s) {
  fprintf(stderr, "consumer: %s: %s\n", what, s->message);
  return 1;
}

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  FILE* f = fopen(argv[1], "rb");
  if (f == NULL) return 2;
  fseek(f, 0, SEEK_END);
  const size_t size = (size_t)ftell(f);
  fseek(f, 0, SEEK_SET);
  void* blob = aligned_block(size);
  if (fread(blob, 1, size, f) != size) return 2;
  fclose(f);

  size_t bytes = 0;
  sinew_rig* rig = NULL;
  sinew_status s = sinew_rig_bytes(blob, size, &bytes);
  if (s.code != SINEW_OK) return fail("sinew_rig_bytes", &s);
  s = sinew_rig_load(blob, size, aligned_block(bytes), bytes, &rig);
  if (s.code != SINEW_OK) return fail("sinew_rig_load", &s);
  s = sinew_layers_bytes(rig, blob, size, &bytes);
  if (s.code != SINEW_OK) return fail("sinew_layers_bytes", &s);
  s = sinew_layers_load(rig, blob, size, aligned_block(bytes), bytes);
  if (s.code != SINEW_OK) return fail("sinew_layers_load", &s);
  free(blob); /* the rig and its layers own copies */

  const sinew_rig_info info = sinew_rig_get_info(rig);
  sinew_pipeline* pipeline = NULL;
  bytes = sinew_pipeline_state_bytes(rig, NULL);
  s = sinew_pipeline_init(rig, NULL, aligned_block(bytes), bytes, &pipeline);
  if (s.code != SINEW_OK) return fail("sinew_pipeline_init", &s);
  const sinew_vertices v = sinew_pipeline_vertices(pipeline);
  const int32_t rest_x = v.x[0], rest_y = v.y[0], rest_z = v.z[0];

  const size_t count = info.input_count + info.external_input_count;
  int32_t* inputs = calloc(count, sizeof(int32_t));
  for (int tick = 0; tick < 200; ++tick) {
    inputs[0] = (int32_t)(tick * 2000000); /* a binary angle: 2^32 = one turn */
    s = sinew_pipeline_step(pipeline, inputs, count);
    if (s.code != SINEW_OK) return fail("sinew_pipeline_step", &s);
  }
  uint64_t hash = 1469598103934665603u; /* FNV-1a over x, y, z */
  const int32_t* axes[3] = {v.x, v.y, v.z};
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < v.count; ++i) {
      uint32_t w = (uint32_t)axes[a][i];
      for (int b = 0; b < 4; ++b, w >>= 8) hash = (hash ^ (w & 0xFF)) * 1099511628211u;
    }
  const int moved = v.x[0] != rest_x || v.y[0] != rest_y || v.z[0] != rest_z;
  printf("joints %u inputs %u vertices %u layers %u moved %d checksum %016llx\n", info.joint_count, info.input_count,
         v.count, info.layer_count, moved, (unsigned long long)hash);
  return moved ? 0 : 1;
}
