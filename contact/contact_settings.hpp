#pragma once
// Contact as a case file asks for it: constants given globally and per body pair, and which
// bodies have self-contact; resolved into one PairLaw per interacting pair of bodies.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "contact/contact_law.hpp"
#include "contact/dem_law.hpp"
#include "contact/point_set.hpp"

namespace ckpd {

class MeshWall;

// What contact needs to know of a body: its points and how it moves.
struct ContactBody {
  PointSet points;
  bool rigid = false;       // no horizon of its own (points.horizon is 0)
  bool prescribed = false;  // its motion is imposed: two such bodies never interact
  // A mesh wall (mesh_wall.hpp): its points are the six carriers of its motion, not contact
  // points; its partners' points meet its surface instead.
  const MeshWall* wall = nullptr;
  std::optional<ElasticConstants> elastic;  // E and nu of its material (dem_law.hpp), if known
  // A DEM sphere (one point at its centre): its radius R; 0 for every other body.
  double sphere_radius = 0;
};

// The default l_c over the larger lattice spacing of the two bodies. THEORY.md suggests about
// 1/2, but a point then slips between the four points of a lattice face (dx/sqrt(2) from the
// face centre) and, in a cubic lattice, down the column of such holes without ever coming
// within l_c of the body: a ball dropped on a plate whose lattice is offset by half a cell
// passes through it. Above 1/sqrt(2) the holes are closed.
inline constexpr double kDefaultRadiusRatio = 0.75;

// Constants that may be given globally or for one pair; a pair's own value wins.
struct ContactConstants {
  std::optional<std::string> law;  // dem_law.hpp; default kDefaultLaw
  // The law's own parameters (one value, or one per side), for the keys it declares.
  std::map<std::string, std::vector<double>> parameters;
  // l_c; default kDefaultRadiusRatio x the larger spacing, or the sum of the two sides' contact
  // radii when a DEM sphere takes part (ContactSettings::law)
  std::optional<double> radius;
  std::optional<double> stiffness;  // Ccon; a pair without one (own or global) has no contact
  std::optional<double> skin;       // default: the radius
  std::optional<double> horizon;    // delta for both sides; default each receiver's own horizon
};

struct ContactPairSetting {
  std::size_t first = 0, second = 0;  // body indices, first <= second; equal: self-contact
  ContactConstants constants;
  bool enabled = true;
};

struct ContactSettings {
  bool present = false;  // the case has a `contact` section
  ContactConstants global;
  std::vector<ContactPairSetting> pairs;
  std::vector<std::size_t> self_contact;  // bodies whose own unbonded points repel (global law)

  // The law between bodies a and b (a == b: self-contact), or nullopt when they do not interact
  // (no stiffness for a law that needs one, disabled, self-contact not asked for, or both
  // prescribed). Throws std::invalid_argument when the pair interacts but no horizon can be found
  // (two rigid bodies without a `horizon`), for an unknown law, or a law's missing parameter.
  //
  // The contact radius l_c of a pair with a DEM sphere, unless the pair gives its own `radius`,
  // is the sum of the two sides' contact radii: R for a sphere, 0 for a mesh wall, and for a
  // point of any other body half the l_c its points have with each other (the global `radius`,
  // else kDefaultRadiusRatio x its spacing). So two spheres touch at R_a + R_b, a sphere and a
  // wall at R, a sphere and a lattice point at R + 0.375 dx by default.
  std::optional<PairLaw> law(const std::vector<ContactBody>& bodies, std::size_t a,
                             std::size_t b) const;
  const ContactPairSetting* pair_setting(std::size_t a, std::size_t b) const;
};

}  // namespace ckpd
