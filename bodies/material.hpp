#pragma once
// Elastic and fracture constants of a CKPD body (THEORY.md sections 3 and 4).
#include <limits>
#include <string>

namespace ckpd {

// How a 2D body is read: per unit thickness of a thin sheet (plane stress) or a slice of a thick
// one (plane strain). 3D bodies use `none`.
enum class PlaneMode { none, stress, strain };

PlaneMode plane_mode_from_string(const std::string& name);  // "stress" | "strain"
std::string to_string(PlaneMode mode);

struct ElasticModuli {
  double lambda;  // first Lame parameter (lambda* = E nu / (1 - nu^2) in plane stress)
  double mu;      // shear modulus
  double bulk;    // K: E/(3(1-2nu)) in 3D, E/(2(1-nu)) plane stress, lambda + mu plane strain
};

// The nonlinear state-based solid's constants (bodies/state_based_model.hpp); other models leave
// them at their defaults.
struct StateBasedConstants {
  double lambda_bar = 0, mu_bar = 0;  // Pa (N/m in 2D)
  double m = 0.5;                     // the Seth-Hill exponent of its bond strain
  // beta of the critical bond energy beta / |xi|^2; infinite: no failure.
  double failure_beta = std::numeric_limits<double>::infinity();
  // Set by make_body: the factor that makes tr_w(1) = d for the fullest family.
  double weight_scale = 0;
};

struct InteractionConstants {
  double c1 = 0;  // one-neighbour (bond) constant
  double c2 = 0;  // two-neighbour (area) constant; 0 means the family is not built
  double c3 = 0;  // three-neighbour (volume) constant; 0 means the family is not built
};

// Throws std::invalid_argument (naming the offending value) unless E > 0 and -1 < nu < 0.5 and
// the dimension/plane mode combination makes sense.
void check_elastic_input(int dimension, double youngs_modulus, double poisson_ratio,
                         PlaneMode plane);

ElasticModuli elastic_moduli(int dimension, double youngs_modulus, double poisson_ratio,
                             PlaneMode plane);

// C1, C2, C3 of THEORY.md section 3 (seed 000 eqs. 4.1, 4.2).
InteractionConstants interaction_constants(int dimension, double youngs_modulus,
                                           double poisson_ratio, PlaneMode plane, double horizon);

// Critical bond stretch from the Griffith energy Gc (THEORY.md section 4, seed 000 eq. 3.3).
double critical_stretch_from_fracture_energy(int dimension, double youngs_modulus,
                                             double poisson_ratio, PlaneMode plane, double horizon,
                                             double fracture_energy);

}  // namespace ckpd
