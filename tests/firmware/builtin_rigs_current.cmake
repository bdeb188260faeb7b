# BuiltinRigs.CheckedInBlobsAreTheCompilersOutput: the blobs the firmware
# embeds (unpacked from firmware/builtin/builtin_rigs.tar.zst into EMBEDDED)
# must be byte for byte what this build's sinew-builtin-rig compiles
# (COMPILED). A rig compiler or layer builder change that moves a blob fails
# here until scripts/update-builtin-rigs.sh refreshes the archive. In a cross
# build the compiled blobs come from the emulated target binary, so this is
# also a cross-platform determinism check of the rig compiler.
foreach(rig arm hand)
  set(embedded "${EMBEDDED}/${rig}.rig")
  set(compiled "${COMPILED}/${rig}.rig")
  foreach(f "${embedded}" "${compiled}")
    if(NOT EXISTS "${f}")
      message(FATAL_ERROR "builtin rig ${rig}: ${f} is missing (build the targets sinew_builtin_rigs and sinew_compiled_builtin_rigs)")
    endif()
  endforeach()
  file(SHA256 "${embedded}" want)
  file(SHA256 "${compiled}" got)
  if(NOT want STREQUAL got)
    file(SIZE "${embedded}" want_size)
    file(SIZE "${compiled}" got_size)
    message(FATAL_ERROR "builtin rig ${rig}: the embedded blob (${want_size} bytes, sha256 ${want}) differs from "
                        "the compiler's output (${got_size} bytes, sha256 ${got}); if the change is intended, run "
                        "scripts/update-builtin-rigs.sh and commit the archive with the golden hashes it moves")
  endif()
  message(STATUS "builtin rig ${rig}: embedded blob = compiler output (sha256 ${got})")
endforeach()
