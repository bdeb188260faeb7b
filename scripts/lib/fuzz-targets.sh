# The libFuzzer targets of the clang build, sourced by scripts/fuzz.sh and
# scripts/fuzz-campaign.sh: one "target:corpus:max_len[:archive]" entry
# each. The corpus names the folder under tests/fuzz/corpus/ (and under the
# build tree's tests/fuzz/corpus/); max_len is the longest input libFuzzer
# makes; "archive" keeps the campaign's inputs in
# tests/fuzz/corpus/<corpus>.campaign.tar.zst rather than as files
# (scripts/fuzz-campaign.sh says why), "archive=NAME" in
# tests/fuzz/corpus/NAME.campaign.tar.zst (two targets reading one seed folder).
# docs/fuzzing.md describes each target.
# shellcheck disable=SC2034  # read by the scripts that source this file
sinew_fuzz_targets="candump_parser_fuzz:candump:4096 can_frame_decoder_fuzz:can_frame:4096 config_parser_fuzz:config:4096
daemon_config_fuzz:daemon_config:4096 rig_loader_fuzz:rig:65536:archive=rig_loader
rig_pipeline_fuzz:rig:65536:archive=rig_pipeline gltf_import_fuzz:gltf:65536:archive
frame_log_reader_fuzz:frame_log:16384 udp_receiver_fuzz:udp:16384"
