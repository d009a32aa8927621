#pragma once
// Row classes of the far field's linear operator (issue 20: "one block row per family shape
// class" on lattice bodies). Row i of the operator (linear_operator.hpp) is built from the sets
// of the centres c in {i} and i's family that hold i, whose vertices are all bonded to i (a
// set's edges are bonds), so everything it reads lies in {i} and i's family: the members'
// positions relative to i, their volumes and effective volumes dV1, dV2, dV3 (the centres'
// weights and the receiving point's volume), the intact flags of their bonds, and body-wide
// constants. Two points of a lattice body whose members, in family order, sit at the same
// integer offsets with the same (bitwise) volumes and effective volumes, and whose members'
// bonds are all intact, have the same row up to the rounding of their positions: one class.
// The key is therefore exact, not a tolerance: a point is put in a class only after its key has
// been compared in full with the class's first point. Points with a failed bond among their
// members (a pre-crack at set-up) and points of bodies off a lattice are classes of their own.
#include <cstdint>
#include <vector>

namespace ckpd {

struct Body;

// Per point, the first point of its class (itself for a class's first point): a class's first
// point has the smallest index of the class.
std::vector<std::uint32_t> operator_row_classes(const Body& body);

}  // namespace ckpd
