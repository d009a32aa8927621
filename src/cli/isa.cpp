#include "src/cli/isa.hpp"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include "ckpd_build_info.hpp"

namespace ckpd::isa {
namespace {

// The extensions, as __builtin_cpu_supports names them, and whether this file (compiled with
// the flags of every other) was compiled to use each. Read here, before the guard's region
// below changes the target, and so the predefined macros.
#if defined(__x86_64__) || defined(__i386__)
#define CKPD_ISA_X86 1
#ifdef __SSE3__
#define CKPD_HAS_SSE3 true
#else
#define CKPD_HAS_SSE3 false
#endif
#ifdef __SSSE3__
#define CKPD_HAS_SSSE3 true
#else
#define CKPD_HAS_SSSE3 false
#endif
#ifdef __SSE4_1__
#define CKPD_HAS_SSE4_1 true
#else
#define CKPD_HAS_SSE4_1 false
#endif
#ifdef __SSE4_2__
#define CKPD_HAS_SSE4_2 true
#else
#define CKPD_HAS_SSE4_2 false
#endif
#ifdef __POPCNT__
#define CKPD_HAS_POPCNT true
#else
#define CKPD_HAS_POPCNT false
#endif
#ifdef __AVX__
#define CKPD_HAS_AVX true
#else
#define CKPD_HAS_AVX false
#endif
#ifdef __AVX2__
#define CKPD_HAS_AVX2 true
#else
#define CKPD_HAS_AVX2 false
#endif
#ifdef __FMA__
#define CKPD_HAS_FMA true
#else
#define CKPD_HAS_FMA false
#endif
#ifdef __BMI__
#define CKPD_HAS_BMI true
#else
#define CKPD_HAS_BMI false
#endif
#ifdef __BMI2__
#define CKPD_HAS_BMI2 true
#else
#define CKPD_HAS_BMI2 false
#endif
#ifdef __AVX512F__
#define CKPD_HAS_AVX512F true
#else
#define CKPD_HAS_AVX512F false
#endif
#ifdef __AVX512VL__
#define CKPD_HAS_AVX512VL true
#else
#define CKPD_HAS_AVX512VL false
#endif
#ifdef __AVX512BW__
#define CKPD_HAS_AVX512BW true
#else
#define CKPD_HAS_AVX512BW false
#endif
#ifdef __AVX512DQ__
#define CKPD_HAS_AVX512DQ true
#else
#define CKPD_HAS_AVX512DQ false
#endif
#ifdef __AVX512CD__
#define CKPD_HAS_AVX512CD true
#else
#define CKPD_HAS_AVX512CD false
#endif
#ifdef __AVX512VBMI__
#define CKPD_HAS_AVX512VBMI true
#else
#define CKPD_HAS_AVX512VBMI false
#endif
#ifdef __AVX512IFMA__
#define CKPD_HAS_AVX512IFMA true
#else
#define CKPD_HAS_AVX512IFMA false
#endif
#ifdef __AVX512VPOPCNTDQ__
#define CKPD_HAS_AVX512VPOPCNTDQ true
#else
#define CKPD_HAS_AVX512VPOPCNTDQ false
#endif
#ifdef __AVX512VBMI2__
#define CKPD_HAS_AVX512VBMI2 true
#else
#define CKPD_HAS_AVX512VBMI2 false
#endif
#ifdef __AVX512VNNI__
#define CKPD_HAS_AVX512VNNI true
#else
#define CKPD_HAS_AVX512VNNI false
#endif
#ifdef __AVX512BITALG__
#define CKPD_HAS_AVX512BITALG true
#else
#define CKPD_HAS_AVX512BITALG false
#endif
#ifdef __AVX512BF16__
#define CKPD_HAS_AVX512BF16 true
#else
#define CKPD_HAS_AVX512BF16 false
#endif

constexpr std::size_t kCount = 22;
constexpr const char* kName[kCount] = {
    "sse3",        "ssse3",      "sse4.1",       "sse4.2",     "popcnt",     "avx",
    "avx2",        "fma",        "bmi",          "bmi2",       "avx512f",    "avx512vl",
    "avx512bw",    "avx512dq",   "avx512cd",     "avx512vbmi", "avx512ifma", "avx512vpopcntdq",
    "avx512vbmi2", "avx512vnni", "avx512bitalg", "avx512bf16"};
constexpr bool kCompiled[kCount] = {
    CKPD_HAS_SSE3,        CKPD_HAS_SSSE3,      CKPD_HAS_SSE4_1,
    CKPD_HAS_SSE4_2,      CKPD_HAS_POPCNT,     CKPD_HAS_AVX,
    CKPD_HAS_AVX2,        CKPD_HAS_FMA,        CKPD_HAS_BMI,
    CKPD_HAS_BMI2,        CKPD_HAS_AVX512F,    CKPD_HAS_AVX512VL,
    CKPD_HAS_AVX512BW,    CKPD_HAS_AVX512DQ,   CKPD_HAS_AVX512CD,
    CKPD_HAS_AVX512VBMI,  CKPD_HAS_AVX512IFMA, CKPD_HAS_AVX512VPOPCNTDQ,
    CKPD_HAS_AVX512VBMI2, CKPD_HAS_AVX512VNNI, CKPD_HAS_AVX512BITALG,
    CKPD_HAS_AVX512BF16};
#else
constexpr std::size_t kCount = 0;
#endif

}  // namespace

std::vector<std::string> compiled_extensions() {
  std::vector<std::string> names;
#ifdef CKPD_ISA_X86
  for (std::size_t k = 0; k < kCount; ++k)
    if (kCompiled[k]) names.emplace_back(kName[k]);
#endif
  return names;
}

// From here on, code for the baseline x86-64 whatever the build's -march: the guard runs on any
// x86-64 CPU, before the first static initialiser of the program, and so it calls only libc and
// compiler built-ins (no inline C++ library function, which would be compiled for the build's
// instruction set).
#if defined(CKPD_ISA_X86) && defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC target("arch=x86-64")
#endif

bool host_has(std::size_t index) {
#ifdef CKPD_ISA_X86
  __builtin_cpu_init();
  switch (index) {
    case 0:
      return __builtin_cpu_supports("sse3") != 0;
    case 1:
      return __builtin_cpu_supports("ssse3") != 0;
    case 2:
      return __builtin_cpu_supports("sse4.1") != 0;
    case 3:
      return __builtin_cpu_supports("sse4.2") != 0;
    case 4:
      return __builtin_cpu_supports("popcnt") != 0;
    case 5:
      return __builtin_cpu_supports("avx") != 0;
    case 6:
      return __builtin_cpu_supports("avx2") != 0;
    case 7:
      return __builtin_cpu_supports("fma") != 0;
    case 8:
      return __builtin_cpu_supports("bmi") != 0;
    case 9:
      return __builtin_cpu_supports("bmi2") != 0;
    case 10:
      return __builtin_cpu_supports("avx512f") != 0;
    case 11:
      return __builtin_cpu_supports("avx512vl") != 0;
    case 12:
      return __builtin_cpu_supports("avx512bw") != 0;
    case 13:
      return __builtin_cpu_supports("avx512dq") != 0;
    case 14:
      return __builtin_cpu_supports("avx512cd") != 0;
    case 15:
      return __builtin_cpu_supports("avx512vbmi") != 0;
    case 16:
      return __builtin_cpu_supports("avx512ifma") != 0;
    case 17:
      return __builtin_cpu_supports("avx512vpopcntdq") != 0;
    case 18:
      return __builtin_cpu_supports("avx512vbmi2") != 0;
    case 19:
      return __builtin_cpu_supports("avx512vnni") != 0;
    case 20:
      return __builtin_cpu_supports("avx512bitalg") != 0;
    case 21:
      return __builtin_cpu_supports("avx512bf16") != 0;
    default:
      return false;
  }
#else
  (void)index;
  return true;
#endif
}

namespace {

void append(char* buffer, std::size_t capacity, const char* text) {
  std::size_t used = std::strlen(buffer);
  while (*text != '\0' && used + 1 < capacity) buffer[used++] = *text++;
  buffer[used] = '\0';
}

// The refusal line into `line` (empty when the host lacks nothing).
void compose_refusal(char* line, std::size_t capacity, bool (*has)(std::size_t)) {
  line[0] = '\0';
#ifdef CKPD_ISA_X86
  char missing[256] = "";
  for (std::size_t k = 0; k < kCount; ++k) {
    if (!kCompiled[k] || has(k)) continue;
    append(missing, sizeof missing, " ");
    append(missing, sizeof missing, kName[k]);
  }
  if (missing[0] == '\0') return;
  append(line, capacity, "ckpd: error: this ckpd was built for CKPD_ARCH=");
  append(line, capacity, build::kArch);
  append(line, capacity, " (");
  append(line, capacity, build::kMarch);
  append(line, capacity, ") and needs");
  append(line, capacity, missing);
  append(line, capacity,
         ", which this CPU lacks; build it for this machine (cmake -DCKPD_ARCH=native, or "
         "x86-64-v3, x86-64-v2, portable)\n");
#else
  (void)capacity;
  (void)has;
#endif
}

// Priority 101: before the static initialisers of default priority in every object of the
// program (the model and condition registries, ...), which may already hold the build's vector
// instructions. Exit status 1: the program cannot run here (2 is for bad input).
__attribute__((constructor(101))) void refuse_a_host_without_the_instruction_set() {
  char line[768];
  compose_refusal(line, sizeof line, host_has);
  if (line[0] == '\0') return;
  const ssize_t written = write(STDERR_FILENO, line, std::strlen(line));
  (void)written;
  _exit(1);
}

}  // namespace

#if defined(CKPD_ISA_X86) && defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

std::string refusal(bool (*has)(std::size_t)) {
  char line[768];
  compose_refusal(line, sizeof line, has);
  return line;
}

}  // namespace ckpd::isa
