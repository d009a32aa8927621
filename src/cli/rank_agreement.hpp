#pragma once
// The ranks of an MPI run compare what each loaded before their first collective: mpirun can
// start them with different command lines (`mpirun -np 1 ckpd run a.yaml : -np 1 ckpd run
// b.yaml`), and each reads the case and its mesh files from its own node. Ranks that differ
// would step different scenes in lockstep (two different cases ran as one job and exited 0) or
// wait for ever in a collective the others never enter.
#include <cstdint>
#include <string>

#include "src/engine/scene.hpp"

namespace ckpd {

// What a rank must share with the others: the resolved case (YAML text, with its --set
// overrides applied), its bodies' points as built (mesh and point-cloud files included), and the
// command line's options that every rank acts on (--out, --restart, --gather-output).
struct LoadedCase {
  std::string resolved_case;
  const Scene* scene = nullptr;
  std::string out, restart;
  bool gather_output = false;
};

// A collective: every rank passes its own. Returns 0 when every rank loaded what rank 0 did;
// otherwise 2 on every rank, with one message on stderr naming the first rank that differs and
// what differs.
int agree_on_loaded_case(const LoadedCase& loaded);

}  // namespace ckpd
