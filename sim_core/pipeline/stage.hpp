// The pipeline's stages and a set of them. The stage table
// (stage_table.hpp) names each; this header only orders them.
#pragma once

#include <cstdint>

namespace sinew::pipeline {

// In the order a tick runs them (docs/pipeline.md).
enum class Stage : uint8_t { kSkinning = 0, kSph, kMetaballs, kBarnet, kAnatomy };
inline constexpr uint32_t kStageCount = 5;

// A set of stages, one bit per Stage. Skinning always runs: its bit is
// ignored where a set switches layers on or off.
struct StageSet {
  uint32_t bits = 0;

  static constexpr StageSet all() { return {(1u << kStageCount) - 1}; }
  static constexpr StageSet none() { return {}; }
  constexpr bool has(Stage s) const { return (bits >> static_cast<uint32_t>(s) & 1u) != 0; }
  constexpr void set(Stage s, bool on) {
    const uint32_t bit = 1u << static_cast<uint32_t>(s);
    bits = on ? (bits | bit) : (bits & ~bit);
  }
  constexpr bool operator==(const StageSet&) const = default;
};

}  // namespace sinew::pipeline
