#pragma once
// The instruction set this binary was compiled for (CKPD_ARCH, CMakeLists.txt) and the check,
// before anything else runs, that the host has it: a binary built with -march=native on a machine
// with AVX-512 refuses, with one line naming what is missing, to start on a CPU without it
// instead of dying of SIGILL at its first AVX-512 instruction.
#include <cstddef>
#include <string>
#include <vector>

namespace ckpd::isa {

// The x86 extensions the compiler was told to use, from its predefined macros (__AVX2__,
// __FMA__, __AVX512F__, ...), as __builtin_cpu_supports names them ("avx2", "fma", "avx512f"),
// in the order of the table in isa.cpp. Empty on a baseline x86-64 build and off x86.
std::vector<std::string> compiled_extensions();

// The refusal for a host on which `host_has(k)` says which entries k of the table it has: one
// line naming the build and each compiled extension the host lacks; empty when it lacks none.
// (The guard calls it with __builtin_cpu_supports; a test with a pretend host.)
std::string refusal(bool (*host_has)(std::size_t index));

// Whether this host has table entry `index` (__builtin_cpu_supports).
bool host_has(std::size_t index);

}  // namespace ckpd::isa
