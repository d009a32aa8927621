#pragma once
// Contact laws registered by name (the LAMMPS pair-style pattern): each law is one file under
// contact/laws/ behind this small interface, registered by name; adding a law touches no other
// file. A body pair chooses its law in the case's `contact` section (`law: NAME`, globally or
// per pair, as the other contact keys) together with the law's own parameters.
//
// `repulsive` (the default) is the seed's law of contact_law.hpp, computed on its own path, bit
// for bit as before. The other laws are DEM laws: every point pair closer than l_c is one
// contact with overlap delta = l_c - r along n = (x^i - x^j)/r (against a mesh wall,
// delta = l_c - h along the wall's outward normal), with
//
//   normal:      F_n = f(delta) - gamma(delta) v_n,        v_n = (v^i - v^j) . n at the contact
//   tangential:  F_t = -k_t(delta) xi, |F_t| <= mu max(F_n, 0)      (tangential_spring.hpp)
//
// on point i (the opposite on j), f and gamma from the law. The masses the damping uses are the
// point masses rho V (a free point has no other); against a wall the wall's side is immovable
// (m* = m^i). A DEM sphere in the usual sense is a rigid body of one point (l_c = R_1 + R_2
// between two, l_c = R against a wall); a rigid body's points carry its spin, and the tangential
// force acts at the contact point (the midpoint of a point pair, the nearest surface point of a
// wall), so it turns the body. A deformable point's bond neighbourhood takes up that couple
// and lends the contact its mean spin instead (point_cluster.hpp).
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ckpd {

// A body's elastic constants, for laws that need them (hertz_mindlin): a deformable body's from
// its material, a rigid body's or mesh wall's from its own `rigid:` keys (or its material).
struct ElasticConstants {
  double youngs_modulus = 0;  // Pa
  double poisson_ratio = 0;
};

// One side of a point pair as a law sees it. A wall side has infinite mass and no volume.
struct LawPoint {
  double volume = 0;  // m^3 (m^2 in 2D)
  double mass = 0;    // kg; +inf for a wall
};

// m* = m_a m_b / (m_a + m_b); an immovable side (infinite mass: a wall, an imposed motion)
// leaves the other's mass.
inline double effective_mass(const LawPoint& a, const LawPoint& b, bool wall) {
  if (wall || std::isinf(b.mass)) return a.mass;
  if (std::isinf(a.mass)) return b.mass;
  return a.mass * b.mass / (a.mass + b.mass);
}

// The law at one overlap.
struct NormalResponse {
  double force = 0;                 // f(delta), N: the elastic normal force, > 0 pushes apart
  double stiffness = 0;             // df/d delta, N/m
  double energy = 0;                // J: the elastic energy stored at delta (f = dU/d delta)
  double damping = 0;               // gamma, N s/m: the normal force is f - gamma v_n
  double tangential_stiffness = 0;  // k_t, N/m
};

class DemLaw {
 public:
  virtual ~DemLaw() = default;
  // At overlap delta > 0 between a and b (b a wall when `wall`).
  virtual NormalResponse normal(double overlap, const LawPoint& a, const LawPoint& b,
                                bool wall) const = 0;
  // The normal damping ratio gamma / (2 sqrt(k m*)) with k the law's tangent stiffness; for
  // Hertz it does not depend on the overlap.
  virtual double damping_ratio() const = 0;
  // Coulomb friction coefficient mu; 0: no tangential force and no history.
  double friction = 0;
};

// One parameter a law reads from the `contact` section.
struct LawParameter {
  std::string key;
  std::string expected;  // what a valid value is, for error messages
  bool required = false;
  std::size_t max_values = 1;  // 2: a scalar or a list of one value per side of the pair
  std::function<bool(double)> valid;
};

struct LawInputs {
  std::map<std::string, std::vector<double>> parameters;  // resolved for the pair, validated
  double radius = 0;                                      // l_c
  // The two sides' contact radii (PairLaw::side_radius) when a DEM sphere takes part, else 0.
  double side_radius[2] = {0, 0};
  double coefficient = 0;  // mean 9 Ccon/(pi delta^5) of the pair (laws that need a stiffness)
  // The two bodies of the pair (side 0, side 1), for laws that use their materials.
  struct Side {
    std::string name;
    bool rigid = false, wall = false;
    std::optional<ElasticConstants> elastic;
  };
  Side side[2];
};

struct LawType {
  std::string summary;  // one line for error messages and `ckpd check`
  std::vector<LawParameter> parameters;
  bool needs_stiffness = false;  // Ccon and a horizon, as the seed law
  // Null for the seed law (its own path); throws std::invalid_argument for inconsistent input.
  std::function<std::shared_ptr<const DemLaw>(const LawInputs&)> make;
};

inline constexpr const char* kDefaultLaw = "repulsive";

std::map<std::string, LawType>& law_registry();
bool register_law(const std::string& name, LawType type);
// The registered names, comma-separated, sorted.
std::string known_laws();
// Null when no law has that name.
const LawType* find_law(const std::string& name);

// Parameter helpers for the law files.
bool valid_restitution(double e);      // 0 < e <= 1
bool valid_non_negative(double x);     // x >= 0
bool valid_positive(double x);         // x > 0
bool valid_poisson(double x);          // -1 < x < 0.5
LawParameter restitution_parameter();  // `restitution`, required
LawParameter friction_parameter();     // `friction`, optional, default 0
// value k of a parameter given as a scalar or a list of one value per side
double side_value(const LawInputs& in, const std::string& key, std::size_t side);
double value_or(const LawInputs& in, const std::string& key, double fallback);

}  // namespace ckpd
