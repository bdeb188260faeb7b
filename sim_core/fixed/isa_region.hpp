// Compiles the functions between SINEW_ISA_BEGIN("isa,...") and SINEW_ISA_END
// for an instruction-set extension (GCC's and Clang's target attribute), the
// rest of the file baseline.
//
// Why not -mavx2 on the whole file: the inline functions of the shared
// headers it includes (sim_core/fixed, <span>, ...) that the compiler emits out
// of line become weak symbols built with the extension, the linker keeps one
// copy of each for the whole program, and it may keep that one for the
// baseline callers too: a CPU without the extension would then fault in code
// that never chose it. Include every shared header before the region; only
// the kernel's own functions go inside it.
#pragma once

#define SINEW_ISA_PRAGMA(x) _Pragma(#x)
#if defined(__clang__)
#define SINEW_ISA_BEGIN(isa) SINEW_ISA_PRAGMA(clang attribute push(__attribute__((target(isa))), apply_to = function))
#define SINEW_ISA_END SINEW_ISA_PRAGMA(clang attribute pop)
#elif defined(__GNUC__)
#define SINEW_ISA_BEGIN(isa) SINEW_ISA_PRAGMA(GCC push_options) SINEW_ISA_PRAGMA(GCC target(isa))
#define SINEW_ISA_END SINEW_ISA_PRAGMA(GCC pop_options)
#else
#error "sim_core's vector kernels need GCC or Clang"
#endif
