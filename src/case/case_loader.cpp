#include "src/case/case_loader.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "bodies/far_field.hpp"
#include "bodies/material.hpp"
#include "bodies/patch_test.hpp"
#include "src/case/contact_loader.hpp"
#include "src/case/keys/case_keys.hpp"
#include "src/case/material_model.hpp"
#include "src/case/rigid_body_loader.hpp"
#include "src/geometry/lattice.hpp"
#include "src/geometry/mesh/mesh_shape.hpp"
#include "src/geometry/point_cloud.hpp"
#include "src/geometry/shape.hpp"
#include "src/geometry/work_estimate.hpp"
#include "src/input/nearest_name.hpp"
#include "src/output/field_writer.hpp"
#include "src/output/history_quantities.hpp"

namespace ckpd {

namespace {

constexpr std::size_t kDefaultMaxPoints = 20'000'000;
// A spacing below a nanometre is no continuum (the material bounds: material_model.hpp).
constexpr double kMinLength = 1e-9;

struct MaterialSpec {
  std::shared_ptr<const MaterialModel> model;  // src/case/material_model.hpp
  CaseNode node;
};

std::map<std::string, MaterialSpec> read_materials(const CaseNode& root) {
  // Optional: rigid bodies and DEM spheres may give their mass, E and nu themselves.
  std::map<std::string, MaterialSpec> materials;
  const auto section = root.optional("materials");
  if (!section) return materials;
  for (const auto& [name, m] : section->entries())
    materials.emplace(name, MaterialSpec{make_material(m), m});
  if (materials.empty()) section->fail("at least one material");
  return materials;
}

std::vector<Precrack> read_precracks(const CaseNode& list, int dimension) {
  std::vector<Precrack> cracks;
  for (const CaseNode& c : list.elements()) {
    Precrack crack;
    for (const CaseNode& corner : c.elements())
      crack.corners.push_back(corner.as_vector(dimension));
    if (dimension == 2 && crack.corners.size() != 2)
      c.fail("a 2D pre-crack as a segment: a list of 2 points");
    if (dimension == 3 && crack.corners.size() < 3)
      c.fail("a 3D pre-crack as a planar polygon: a list of 3 or more corners");
    cracks.push_back(std::move(crack));
  }
  return cracks;
}

// The memory the bodies will take, charged body by body before each is built and refused
// against the case's max_memory (bytes) or the machine's available memory.
struct MemoryBudget {
  std::uint64_t limit = 0;  // 0: unknown (no /proc/meminfo), nothing is refused
  std::string source;       // "max_memory" or "the available memory (MemAvailable)"
  std::uint64_t used = 0;

  void charge(const CaseNode& body, const std::string& name, std::uint64_t points,
              std::uint64_t family) {
    const std::uint64_t bytes = body_bytes_estimate(points, family);
    used = saturating_add(used, bytes);
    if (limit && used > limit) {
      std::ostringstream msg;
      msg << body.where() << ": body '" << name << "' needs at least " << format_bytes(bytes)
          << " (" << format_count(points) << " points x about " << format_count(family)
          << " bonds each, " << format_count(saturating_mul(points, family)) << " bonds), "
          << format_bytes(used) << " with the bodies before it, over " << source << " of "
          << format_bytes(limit) << " (coarsen the spacing, lower the horizon ratio"
          << (source == "max_memory" ? ", or raise max_memory)" : ")");
      throw CaseError(msg.str());
    }
  }
};

// The force form and damage rule of a body whose case leaves them out: the one place that
// chooses them (README, "force_form"; docs/VALIDATION.md, "The default"). A CKPD body gets
// force_form energy_consistent with damage_rule all_edges: its forces are -(1/V) grad E of the
// strain energy it reports, so momentum holds to round-off and the energy balance closes to
// second order in dt under fracture, and it stayed stable in every validation scene, where
// energy_consistent with centre_bonds did not. A body of another force model (model: pmb,
// state_based) keeps own_family (its forces are its own) and centre_bonds (it has no two- or
// three-neighbour sets, so the rule would change nothing but the failure pass's cost). The
// seed's law stays available by name: force_form: own_family, damage_rule: centre_bonds. Code
// that fills a BodyDefinition itself (the kernel tests, the reference oracle's comparisons)
// gets the struct's own initial values, the seed's law.
void apply_default_laws(BodyDefinition& def, bool form_given, bool rule_given) {
  const bool ckpd = def.model == nullptr;
  if (!form_given) def.force_form = ckpd ? ForceForm::energy_consistent : ForceForm::own_family;
  if (!rule_given) def.damage_rule = ckpd ? DamageRule::all_edges : DamageRule::centre_bonds;
}

SceneBody read_body(const CaseNode& n, const std::map<std::string, MaterialSpec>& materials,
                    MemoryBudget& budget) {
  if (n.has("rigid")) {
    // A rigid body's material, when it has one, gives only its density and (for contact laws
    // that use them) its E and nu.
    std::optional<double> density;
    std::optional<ElasticConstants> elastic;
    if (auto m = n.optional("material")) {
      const auto it = materials.find(m->as_string());
      if (it == materials.end()) m->fail("the name of a material in `materials`");
      density = it->second.model->density();
      elastic = it->second.model->elastic();
    }
    return read_rigid_body(n, density, elastic);
  }
  BodyDefinition def;
  def.name = n.required("name").as_string();
  const CaseNode material_node = n.required("material");
  const auto mit = materials.find(material_node.as_string());
  if (mit == materials.end())
    material_node.fail(materials.empty() ? "a material in a `materials` section (the case has none)"
                                         : "the name of a material in `materials`");
  const MaterialSpec& mat = mit->second;

  def.dimension = 3;
  if (auto d = n.optional("dimension")) {
    def.dimension = static_cast<int>(d->as_integer());
    if (def.dimension != 2 && def.dimension != 3) d->fail("2 or 3");
  }
  PlaneMode plane = def.dimension == 2 ? PlaneMode::stress : PlaneMode::none;
  if (auto p = n.optional("plane")) {
    if (def.dimension != 2) p->fail("no `plane` key on a 3D body");
    try {
      plane = plane_mode_from_string(p->as_string());
    } catch (const std::invalid_argument&) {
      p->fail("'stress' or 'strain'");
    }
  }
  const double spacing =
      n.required("spacing").as_in_range(kMinLength, kMaxCoordinate, "a spacing in m");
  const auto horizon_node = n.optional("horizon");
  const auto ratio_node = n.optional("horizon_ratio");
  if (horizon_node && ratio_node) n.fail("either horizon or horizon_ratio, not both");
  if (!horizon_node && !ratio_node) n.fail("a horizon (or horizon_ratio = horizon / spacing)");
  def.horizon = horizon_node ? horizon_node->as_positive() : ratio_node->as_positive() * spacing;
  const CaseNode& horizon_key = horizon_node ? *horizon_node : *ratio_node;
  if (def.horizon < spacing) {
    std::ostringstream msg;
    msg << "a horizon of at least the spacing (" << spacing << " m), else no point has a bond; got "
        << def.horizon << " m";
    horizon_key.fail(msg.str());
  }
  // The family's size sets the set-up cost (its square or cube) and the memory per point.
  const std::uint64_t family = family_size_estimate(def.dimension, def.horizon / spacing);
  if (family > kMaxFamilySize) {
    std::ostringstream msg;
    msg << "a horizon / spacing whose family holds at most " << kMaxFamilySize
        << " lattice offsets; horizon / spacing = " << def.horizon / spacing << " gives about "
        << format_count(family);
    horizon_key.fail(msg.str());
  }

  std::size_t max_points = kDefaultMaxPoints;
  if (auto m = n.optional("max_points")) {
    const long long v = m->as_integer();
    if (v <= 0) m->fail("a positive point limit");
    max_points = static_cast<std::size_t>(v);
  }
  // The points come from a shape sampled on a lattice or from a point-cloud file.
  const auto geometry_node = n.optional("geometry");
  const auto points_node = n.optional("points");
  if (geometry_node && points_node) n.fail("either geometry or points, not both");
  if (!geometry_node && !points_node) n.fail("a geometry (a shape) or points (a point-cloud file)");
  LatticeSample sample;
  std::optional<MeshInfo> mesh_info;  // for `ckpd check`
  if (points_node) {
    sample = load_point_cloud(*points_node, def.dimension, spacing, def.horizon, max_points);
  } else {
    const CaseNode& geometry = *geometry_node;
    const std::unique_ptr<Shape> shape = make_shape(geometry, def.dimension);
    if (const auto* m = dynamic_cast<const MeshShape*>(shape.get())) mesh_info = m->info();
    try {
      sample = sample_lattice(*shape, def.dimension, spacing, def.horizon, max_points);
    } catch (const std::invalid_argument& e) {
      geometry.fail(std::string("a geometry that can be sampled (") + e.what() + ")");
    }
    if (sample.position.empty()) {
      std::ostringstream msg;
      msg << geometry.where() << ": body '" << def.name
          << "' has no points: the geometry holds no lattice site at spacing " << spacing << " m";
      throw CaseError(msg.str());
    }
  }
  budget.charge(n, def.name, sample.position.size(), family);
  if (auto b = n.optional("beta")) {
    // strict: a family fuller than the reference is an error; capped: beta = min(raw, 1),
    // with the count of capped points reported (README, "Point clouds").
    const std::string policy = b->as_string();
    if (policy != "strict" && policy != "capped") b->fail("'strict' or 'capped'");
    def.cap_beta = policy == "capped";
  }
  if (auto f = n.optional("degenerate_fraction")) {
    // Sets with |A| <= f L L (|V| <= f L L L) are left out (BodyDefinition::degenerate_fraction).
    def.degenerate_fraction = f->as_positive();
    if (def.degenerate_fraction >= 1) f->fail("a fraction in (0, 1)");
  }
  if (auto f = n.optional("inversion_penalty")) {
    // Energy penalty on inverted tetrahedra (triangles in 2D): BodyDefinition::inversion_penalty.
    def.inversion_penalty = f->as_double();
    if (!(def.inversion_penalty >= 0)) f->fail("a penalty factor >= 0 (0: off, 1: signed volume)");
  }
  std::optional<CaseNode> damage_rule_node = n.optional("damage_rule");
  if (auto f = damage_rule_node) {
    // Which failed bonds switch a triangle or tetrahedron off (BodyDefinition::damage_rule).
    const std::string rule = f->as_string();
    if (rule != "centre_bonds" && rule != "all_edges") f->fail("'centre_bonds' or 'all_edges'");
    def.damage_rule = damage_rule_from_string(rule);
  }
  std::optional<CaseNode> force_form_node = n.optional("force_form");
  if (force_form_node) {
    // How the CKPD forces follow from the energy (BodyDefinition::force_form, THEORY.md 2b).
    const std::string form = force_form_node->as_string();
    if (form != "own_family" && form != "energy_consistent")
      force_form_node->fail("'own_family' or 'energy_consistent'");
    def.force_form = force_form_from_string(form);
  }
  // far_field: {tolerance: T, corotated: B}: points whose family is undamaged and whose bond
  // vectors change by less than T L (corotated: once the family's rotation is taken out) take
  // the linear operator's force (bodies/far_field.hpp); T = 0: off.
  std::optional<CaseNode> far_field_node = n.optional("far_field");
  double far_tolerance = 0;
  bool far_corotated = false;
  if (far_field_node) {
    if (!far_field_node->is_map())
      far_field_node->fail(
          "a map {tolerance: T, corotated: true|false} (T >= 0, the largest relative bond-vector "
          "change of a linear point; 0: off)");
    far_tolerance = far_field_node->required("tolerance").as_non_negative();
    if (auto c = far_field_node->optional("corotated")) far_corotated = c->as_bool();
    far_field_node->finish();
  }
  // lattice_stencil: false keeps the general kernel path on a lattice body (comparisons).
  if (auto f = n.optional("lattice_stencil")) def.lattice_stencil = f->as_bool();
  // constants: analytic (THEORY.md section 3, default) or calibrated to the lattice's patch
  // test (bodies/patch_test.hpp: exact bulk and uniaxial-strain moduli for this spacing and m).
  bool calibrated = false;
  std::optional<CaseNode> constants_node = n.optional("constants");
  if (constants_node) {
    const std::string kind = constants_node->as_string();
    if (kind != "analytic" && kind != "calibrated")
      constants_node->fail("'analytic' or 'calibrated'");
    calibrated = kind == "calibrated";
  }
  def.reference_position = std::move(sample.position);
  def.volume = std::move(sample.volume);
  def.full_family_volume = sample.full_family_volume;
  def.density = mat.model->density();

  try {
    mat.model->define(def, MaterialTarget{def.dimension, plane, def.horizon, spacing, calibrated});
  } catch (const std::invalid_argument& e) {
    if (calibrated)
      constants_node->fail(std::string("calibrated constants for body '") + def.name + "' (" +
                           e.what() + ")");
    mat.node.fail(std::string("constants valid for body '") + def.name + "' (" + e.what() + ")");
  }

  // The force form is a CKPD option; other models' forces are their own (PMB's pairwise ones
  // are already the gradient of one energy).
  if (force_form_node && def.model != nullptr && def.force_form != ForceForm::own_family)
    force_form_node->fail("own_family (energy_consistent is a CKPD option; body '" + def.name +
                          "' has force model " + def.model->name + ")");
  apply_default_laws(def, force_form_node.has_value(), damage_rule_node.has_value());
  if (auto p = n.optional("precracks")) def.precracks = read_precracks(*p, def.dimension);
  if (auto zones = n.optional("no_failure")) {
    def.no_failure.assign(def.reference_position.size(), 0);
    for (const CaseNode& z : zones->elements()) {
      const std::unique_ptr<Shape> zone = make_shape(z, def.dimension);
      std::size_t hits = 0;
      for (std::size_t i = 0; i < def.reference_position.size(); ++i)
        if (zone->contains(def.reference_position[i])) {
          def.no_failure[i] = 1;
          ++hits;
        }
      if (!hits) z.fail("a no-failure zone that holds at least one point");
    }
  }
  n.finish();

  SceneBody sb;
  try {
    sb.body = make_body(std::move(def));
  } catch (const std::invalid_argument& e) {
    throw CaseError(n.where() + ": " + e.what());
  }
  if (far_tolerance > 0) {
    try {
      sb.far_field =
          std::make_shared<FarField>(make_far_field(sb.body, far_tolerance, far_corotated));
    } catch (const std::invalid_argument& e) {
      far_field_node->fail(std::string("a body whose force model has a linearisation (") +
                           e.what() + ")");
    }
  }
  sb.spacing = spacing;
  sb.mesh = mesh_info;
  sb.elastic = mat.model->elastic();
  return sb;
}

void read_conditions(const CaseNode& list, Scene& scene) {
  for (const CaseNode& c : list.elements()) {
    const CaseNode body_node = c.required("body");
    const std::string name = body_node.as_string();
    SceneBody* target = nullptr;
    for (SceneBody& sb : scene.bodies)
      if (sb.body.name == name) target = &sb;
    if (!target) body_node.fail("the name of a body in `bodies`");
    if (target->rigid) {
      // A rigid body's motion is its `rigid` setting; loads (gravity, pulses) still apply.
      const CaseNode type = c.required("type");
      const std::string t = type.as_string();
      if (t == "velocity" || t == "fixed" || t == "initial_velocity")
        type.fail("a load on rigid body '" + name + "' (its motion is set by `rigid`)");
    }
    std::unique_ptr<Condition> condition =
        make_condition(c, ConditionTarget{target->body, target->spacing});
    // Two conditions prescribing the same component of the same point contradict each other.
    const std::uint8_t mask = condition->prescribed_components();
    if (mask) {
      for (const auto& other : target->conditions) {
        const std::uint8_t both = mask & other->prescribed_components();
        if (!both) continue;
        const auto& a = condition->points();
        const auto& b = other->points();
        std::vector<std::uint8_t> marked(target->body.size(), 0);
        for (auto i : b) marked[i] = 1;
        for (auto i : a)
          if (marked[i])
            c.fail(
                "a condition that does not prescribe the motion of points another condition "
                "already prescribes (point " +
                std::to_string(i) + " of body '" + name + "')");
      }
    }
    target->conditions.push_back(std::move(condition));
  }
}

TimeSettings read_time(const CaseNode& t) {
  TimeSettings s;
  const auto end = t.optional("end");
  const auto steps = t.optional("steps");
  if (end && steps) t.fail("either end (a time in s) or steps, not both");
  if (!end && !steps) t.fail("an end time (end) or a number of steps (steps)");
  if (end) {
    s.end_time = end->as_positive();
    s.end_where = end->where();
  }
  if (steps) {
    s.steps = steps->as_integer();
    if (s.steps < 0 || s.steps > TimeSettings::kMaxSteps)
      steps->fail("a number of steps from 0 to " + std::to_string(TimeSettings::kMaxSteps));
  }
  if (auto dt = t.optional("dt")) {
    if (!(dt->is_scalar() && dt->as_string() == "auto")) {
      s.dt = dt->as_positive();
      s.dt_where = dt->where();
    }
  }
  if (auto f = t.optional("safety")) {
    s.safety = f->as_positive();
    if (s.safety > 1) f->fail("a safety factor in (0, 1]");
  }
  if (auto a = t.optional("allow_unstable_dt")) s.allow_unstable_dt = a->as_bool();
  if (auto a = t.optional("step_mode")) {
    const std::string mode = a->is_scalar() ? a->as_string() : std::string();
    if (mode == "adaptive")
      s.adaptive_step = true;
    else if (mode != "fixed")
      a->fail(
          "fixed (dt for the whole run) or adaptive (the step follows the stable step at the "
          "current state, never above dt)");
  }
  if (auto f = t.optional("smallest_step")) {
    s.smallest_step = f->as_positive();
    if (!s.adaptive_step)
      f->fail("only with step_mode: adaptive (a fixed step never falls; the guard stops the run)");
  }
  t.finish();
  return s;
}

// Everything but `time`, `output`, `description` and `max_memory`, as YAML: a checkpoint can
// be continued with a later end time or other output, but not with other physics.
std::string physics_text(const YAML::Node& root) {
  YAML::Node physics;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "time" && key != "output" && key != "description" && key != "max_memory")
      physics[key] = kv.second;
  }
  return YAML::Dump(physics);
}

// FNV-1a of the physics text, 16 hex digits.
std::string physics_fingerprint(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  std::ostringstream hex;
  hex << std::hex << std::setw(16) << std::setfill('0') << h;
  return hex.str();
}

// One entry of output.history: {quantity: NAME, body: B} (or bodies: [A, B] for the contact
// quantities), reaction_force with a region of its body; `name` sets the column prefix.
HistoryQuantity read_history_quantity(const CaseNode& e, const Scene& scene) {
  HistoryQuantity q;
  const CaseNode quantity = e.required("quantity");
  q.quantity = quantity.as_string();
  const HistoryQuantityKind* kind = find_history_quantity(q.quantity);
  if (!kind)
    quantity.fail("a history quantity" +
                  did_you_mean(q.quantity, row_names(history_quantity_table())) +
                  " (known: " + known_history_quantities() + ")");
  auto body_index = [&](const CaseNode& n) {
    const std::string name = n.as_string();
    std::vector<std::string> names;
    for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
      if (scene.bodies[k].body.name == name) return k;
      names.push_back(scene.bodies[k].body.name);
    }
    n.fail("a body's name" + did_you_mean(name, names) + " (bodies: " + join_names(names) + ")");
  };
  std::string label = q.quantity;
  if (kind->bodies == 1) {
    q.bodies.push_back(body_index(e.required("body")));
  } else {
    const CaseNode list = e.required("bodies");
    const std::vector<CaseNode> names = list.elements();
    if (names.size() != 2) list.fail("two body names, [first, second]");
    for (const CaseNode& n : names) q.bodies.push_back(body_index(n));
  }
  for (std::size_t k : q.bodies) label += "_" + scene.bodies[k].body.name;
  if (kind->region) {
    const SceneBody& sb = scene.bodies[q.bodies[0]];
    q.points = select_points(e.required("region"), ConditionTarget{sb.body, sb.spacing});
  }
  if (auto n = e.optional("name")) label = n->as_string();
  q.label = label;
  if (const std::string problem = history_quantity_problem(scene, q); !problem.empty())
    e.fail(q.quantity + " of " + problem);
  e.finish();
  return q;
}

// `--set time.steps=N` on a case with `time.end` (or `--set time.end=T` on one with
// `time.steps`) replaces the other: the two are alternatives, and the override is the choice
// (the last such override, when there are several).
void drop_replaced_time_key(YAML::Node& root, const std::vector<CaseNode::Override>& applied) {
  const char* other = nullptr;
  for (const CaseNode::Override& o : applied) {
    const std::string key = o.text.substr(0, o.text.find('='));
    if (key == "time.steps") other = "end";
    if (key == "time.end") other = "steps";
  }
  if (other && root["time"].IsMap() && root["time"][other]) root["time"].remove(other);
}

}  // namespace

Scene load_scene(const std::string& case_file, const std::vector<std::string>& overrides) {
  std::vector<CaseNode::Override> applied;
  YAML::Node resolved = load_case_yaml(case_file, overrides, &applied);
  return load_scene(resolved, case_file, std::move(applied));
}

Scene load_scene(YAML::Node resolved, const std::string& case_file,
                 std::vector<CaseNode::Override> applied) {
  if (!resolved.IsMap())
    throw CaseError(case_file + ": a case is a map of sections (materials, bodies, ...)");
  drop_replaced_time_key(resolved, applied);
  CaseNode root(resolved, case_file);
  root.set_overrides(std::move(applied));
  root.set_key_section(&case_key_section());
  Scene scene;
  scene.case_file = case_file;
  scene.physics = physics_text(resolved);
  scene.fingerprint = physics_fingerprint(scene.physics);
  if (auto d = root.optional("description")) d->as_string();
  const auto materials = read_materials(root);
  MemoryBudget budget;
  if (auto m = root.optional("max_memory")) {
    budget.limit = saturating_count(m->as_in_range(1e6, 1e18, "a memory limit in bytes"));
    budget.source = "max_memory";
  } else {
    budget.limit = default_memory_budget();
    budget.source = "the available memory (MemAvailable)";
  }
  const CaseNode bodies = root.required("bodies");
  for (const CaseNode& b : bodies.elements()) {
    SceneBody sb = read_body(b, materials, budget);
    for (const SceneBody& other : scene.bodies)
      if (other.body.name == sb.body.name) b.fail("a body name used once (" + sb.body.name + ")");
    scene.bodies.push_back(std::move(sb));
  }
  if (scene.bodies.empty()) bodies.fail("at least one body");
  if (auto c = root.optional("conditions")) read_conditions(*c, scene);
  if (auto c = root.optional("contact")) scene.contact = read_contact(*c, scene);
  scene.time = read_time(root.required("time"));
  if (auto o = root.optional("output")) {
    if (auto h = o->optional("history_interval")) {
      scene.output.history_interval = h->as_integer();
      if (scene.output.history_interval <= 0) h->fail("a positive number of steps");
    }
    if (auto c = o->optional("checkpoint_interval")) {
      scene.output.checkpoint_interval = c->as_integer();
      if (scene.output.checkpoint_interval <= 0) c->fail("a positive number of steps");
    }
    if (auto h = o->optional("history"))
      for (const CaseNode& e : h->elements())
        scene.output.history.push_back(read_history_quantity(e, scene));
    const auto steps = o->optional("field_interval");
    const auto seconds = o->optional("field_time_interval");
    if (steps && seconds) o->fail("either field_interval (steps) or field_time_interval (s)");
    if (steps) {
      scene.output.field_interval = steps->as_integer();
      if (scene.output.field_interval <= 0) steps->fail("a positive number of steps");
    }
    if (seconds) scene.output.field_time_interval = seconds->as_positive();
    if (auto f = o->optional("fields")) {
      if (!steps && !seconds) f->fail("fields together with field_interval or field_time_interval");
      for (const CaseNode& name : f->elements()) {
        const std::string field = name.as_string();
        if (!find_field(field)) name.fail("a field name (" + known_field_list() + ")");
        scene.output.fields.push_back(field);
      }
    } else if (steps || seconds) {
      scene.output.fields = {"position", "displacement", "velocity", "damage", "body_id"};
    }
    o->finish();
  }
  root.finish();
  return scene;
}

}  // namespace ckpd
