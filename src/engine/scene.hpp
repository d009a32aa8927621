#pragma once
// What a run needs, assembled from a case file: the bodies with their conditions, contact, the
// time and output settings.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/far_field.hpp"
#include "contact/contact_settings.hpp"
#include "contact/mesh_wall.hpp"
#include "src/engine/condition.hpp"
#include "src/engine/rigid_body.hpp"
#include "src/geometry/mesh/mesh_info.hpp"
#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

struct SceneBody {
  Body body;
  double spacing = 0;  // lattice spacing dx
  std::vector<std::unique_ptr<Condition>> conditions;
  std::optional<RigidMotion> rigid;  // set: a rigid body (no bonds; body holds its points)
  // A DEM sphere (a rigid body of one point at its centre with the solid sphere's inertia): its
  // radius R, which sets its contact radius (contact_settings.hpp); 0 for every other body.
  double sphere_radius = 0;
  // A mesh wall: a rigid body given by its surface; `body` holds its six carrier points.
  std::shared_ptr<const MeshWall> wall;
  // The wall's triangles in the reference frame, for field output (the wall moves them rigidly).
  std::shared_ptr<const TriangleMesh> wall_surface;
  std::optional<MeshInfo> mesh;  // bodies from a mesh (sampled or walls), for `ckpd check`
  // E and nu: a deformable body's material's, a rigid body's own (`rigid: {youngs_modulus,
  // poisson_ratio}`) or its material's; none when unknown. Contact laws that need them read them.
  std::optional<ElasticConstants> elastic;
  // `far_field: {tolerance: T}` with T > 0: the adaptive linearised far field (far_field.hpp);
  // null: every point exact (the default).
  std::shared_ptr<FarField> far_field;
};

struct TimeSettings {
  // The most steps a run plans (time.steps, or time.end over dt): far beyond any run (a million
  // steps a second for eleven days), and step x dt stays exact in a double.
  static constexpr long long kMaxSteps = 1'000'000'000'000;
  double end_time = std::numeric_limits<double>::quiet_NaN();  // run until this time, or
  long long steps = -1;                                        // this many steps
  std::string end_where;     // "case.yaml:12: time.end", for errors about the case's end time
  std::optional<double> dt;  // none: safety x the stable-step estimate
  std::string dt_where;      // "case.yaml:12: time.dt", for errors about the case's dt
  double safety = 0.8;
  bool allow_unstable_dt = false;  // accept a dt above the estimate
  // `step_mode: adaptive`: after each force evaluation the next step is min(dt, safety x the stable
  // step at the current state) for bodies whose measure stiffens in compression (Seth-Hill
  // m <= 0); `step_mode: fixed` (the default): dt for the whole run, with the current-state guard.
  bool adaptive_step = false;
  // Adaptive only: the run stops (as unstable, naming the body and point) when the next step
  // would fall below this; 0: 1e-12 x dt, a step that no run completes with (time.smallest_step).
  double smallest_step = 0;
};

// A history column group chosen in the case (`output: {history: [...]}`), computed by
// src/output/history_quantities.hpp.
struct HistoryQuantity {
  std::string quantity;               // its name in the case: momentum, reaction_force, ...
  std::vector<std::size_t> bodies;    // one body, or two (contact_force, contact_energy)
  std::vector<std::uint32_t> points;  // reaction_force: the region's points of the body
  std::string label;                  // column prefix: "momentum_ball", "reaction_force_bar_grip"
};

struct OutputSettings {
  std::vector<HistoryQuantity> history;  // columns after the default ones
  long long history_interval = 0;        // steps between history rows; 0: about 200 rows in the run
  // Field frames (HDF5 + XDMF): every `field_interval` steps or every `field_time_interval`
  // seconds of simulated time; neither set means no field output at all.
  std::vector<std::string> fields;
  long long field_interval = 0;
  double field_time_interval = 0;
  long long checkpoint_interval = 0;  // steps between checkpoints; 0: only on SIGINT/SIGTERM
  // Not a case key (`ckpd run --gather-output`): the ranks of a distributed run leave the frames
  // and checkpoints to rank 0, which gathers their points (src/output/output_share.hpp).
  bool gather_files = false;
  bool writes_fields() const { return field_interval > 0 || field_time_interval > 0; }
};

struct Scene {
  std::string case_file;
  std::string fingerprint;  // of the case's physics (not its time or output settings)
  std::string physics;      // the YAML the fingerprint hashes: a checkpoint keeps it, so that a
                            // restart from another case can name the key that differs
  std::vector<SceneBody> bodies;
  ContactSettings contact;
  TimeSettings time;
  OutputSettings output;
};

}  // namespace ckpd
