#include "src/output/field_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bodies/damage.hpp"
#include "bodies/point_stress.hpp"
#include "bodies/state_based_model.hpp"
#include "src/input/nearest_name.hpp"
#include "src/output/point_strain.hpp"

namespace ckpd {

namespace {

// A row for a per-point vector: `get(body, i)` gives the value at point i.
template <class Get>
FieldSpec vector_field(std::string name, std::string description, Get get) {
  return {std::move(name),
          3,
          FieldNumber::float64,
          false,
          std::move(description),
          [get](const FieldSource& source, std::vector<double>& out) {
            const Body& body = source.body;
            out.resize(3 * body.size());
            for (std::size_t i = 0; i < body.size(); ++i) {
              const Vec3 v = get(body, i);
              for (int k = 0; k < 3; ++k) out[3 * i + k] = v[k];
            }
          }};
}

template <class Get>
FieldSpec scalar_field(std::string name, FieldNumber number, std::string description, Get get) {
  return {std::move(name),
          1,
          number,
          false,
          std::move(description),
          [get](const FieldSource& source, std::vector<double>& out) {
            const Body& body = source.body;
            out.resize(body.size());
            for (std::size_t i = 0; i < body.size(); ++i) out[i] = get(source, i);
          }};
}

std::vector<FieldSpec> make_table() {
  std::vector<FieldSpec> t;
  t.push_back(vector_field("position", "current position x = X + u, m",
                           [](const Body& b, std::size_t i) { return b.current_position(i); }));
  t.push_back(vector_field("reference_position", "reference position X, m",
                           [](const Body& b, std::size_t i) { return b.reference_position[i]; }));
  t.push_back(vector_field("displacement", "u, m",
                           [](const Body& b, std::size_t i) { return b.displacement[i]; }));
  t.push_back(
      vector_field("velocity", "m/s", [](const Body& b, std::size_t i) { return b.velocity[i]; }));
  t.push_back(vector_field("force_density", "internal + external + contact force per volume, N/m^3",
                           [](const Body& b, std::size_t i) { return b.force_density[i]; }));
  t.push_back({"damage", 1, FieldNumber::float64, false,
               "fraction of the point's bonds that failed during the run",
               [](const FieldSource& source, std::vector<double>& out) {
                 point_damage(source.body, out);
               }});
  t.push_back({"free_surface", 1, FieldNumber::float64, false,
               "D = 1 - tr_w(phi) / d, the state-based weight over intact bonds (seed 002): 0 "
               "inside, about 1/2 on a flat surface",
               [](const FieldSource& source, std::vector<double>& out) {
                 state_based_free_surface(source.body, out, source.whole);
               }});
  t.push_back({"strain_energy_density", 1, FieldNumber::float64, true, "J/m^3 (J/m^2 in 2D)",
               [](const FieldSource& source, std::vector<double>& out) {
                 const Body& body = source.body;
                 out.assign(body.strain_energy_density.begin(), body.strain_energy_density.end());
               }});
  t.push_back(
      scalar_field("volume", FieldNumber::float64, "the point's volume, m^3 (area in 2D)",
                   [](const FieldSource& source, std::size_t i) { return source.body.volume[i]; }));
  t.push_back(scalar_field(
      "body_id", FieldNumber::int32, "index of the body in the case's list",
      [](const FieldSource& source, std::size_t) { return static_cast<double>(source.index); }));
  t.push_back(scalar_field(
      "point_id", FieldNumber::int32, "index of the point in its body (as in checkpoints)",
      [](const FieldSource& source, std::size_t i) {
        return static_cast<double>(source.whole_index ? (*source.whole_index)[i] : i);
      }));
  t.push_back({"deformation_gradient", 9, FieldNumber::float64, false,
               "non-local F (correspondence estimate over intact bonds), row-major",
               [](const FieldSource& source, std::vector<double>& out) {
                 const Body& body = source.body;
                 out.resize(9 * body.size());
                 for (std::size_t i = 0; i < body.size(); ++i) {
                   const Eigen::Matrix3d F = deformation_gradient(body, i);
                   for (int r = 0; r < 3; ++r)
                     for (int c = 0; c < 3; ++c) out[9 * i + 3 * r + c] = F(r, c);
                 }
               }});
  t.push_back({"green_lagrange_strain", 6, FieldNumber::float64, false,
               "E = (F^T F - I) / 2 (xx, xy, xz, yy, yz, zz)",
               [](const FieldSource& source, std::vector<double>& out) {
                 const Body& body = source.body;
                 out.resize(6 * body.size());
                 for (std::size_t i = 0; i < body.size(); ++i) {
                   const Eigen::Matrix3d F = deformation_gradient(body, i);
                   const Eigen::Matrix3d E =
                       0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
                   const double v[6] = {E(0, 0), E(0, 1), E(0, 2), E(1, 1), E(1, 2), E(2, 2)};
                   for (int k = 0; k < 6; ++k) out[6 * i + k] = v[k];
                 }
               }});
  t.push_back({"dilatation", 1, FieldNumber::float64, false,
               "det F - 1: relative change of volume (area in 2D)",
               [](const FieldSource& source, std::vector<double>& out) {
                 const Body& body = source.body;
                 out.resize(body.size());
                 for (std::size_t i = 0; i < body.size(); ++i)
                   out[i] = deformation_gradient(body, i).determinant() - 1;
               }});
  t.push_back({"stress", 6, FieldNumber::float64, false,
               "Cauchy stress from the virial of the point's own energy, tau / det F (xx, xy, "
               "xz, yy, yz, zz), Pa; computed only for frames that write it",
               [](const FieldSource& source, std::vector<double>& out) {
                 const Body& body = source.body;
                 out.resize(6 * body.size());
                 if (body.family.offset.size() != body.size() + 1) {  // rigid: no stress
                   std::fill(out.begin(), out.end(), std::numeric_limits<double>::quiet_NaN());
                   return;
                 }
                 std::vector<Eigen::Matrix3d> tau;
                 kirchhoff_stress(body, tau);
                 for (std::size_t i = 0; i < body.size(); ++i) {
                   // The current volume J V^i; a point without an estimate of F (its intact
                   // bonds do not span its dimension) keeps its reference volume.
                   const double J = deformation_gradient(body, i).determinant();
                   const Eigen::Matrix3d s =
                       0.5 * (tau[i] + tau[i].transpose()) / (std::isfinite(J) && J > 0 ? J : 1.0);
                   const double v[6] = {s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)};
                   for (int k = 0; k < 6; ++k) out[6 * i + k] = v[k];
                 }
               }});
  return t;
}

}  // namespace

const std::vector<FieldSpec>& field_table() {
  static const std::vector<FieldSpec> table = make_table();
  return table;
}

const FieldSpec* find_field(const std::string& name) {
  return find_row(field_table(), name);
}

const std::vector<std::string>& known_field_names() {
  static const std::vector<std::string> names = row_names(field_table());
  return names;
}

std::string known_field_list() {
  return join_names(known_field_names());
}

const char* xdmf_attribute_type(int components) {
  switch (components) {
    case 3:
      return "Vector";
    case 6:
      return "Tensor6";
    case 9:
      return "Tensor";
    default:
      return "Scalar";
  }
}

}  // namespace ckpd
