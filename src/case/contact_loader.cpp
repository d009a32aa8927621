#include "src/case/contact_loader.hpp"

#include <stdexcept>
#include <utility>

#include "contact/dem_law.hpp"
#include "src/engine/contact_coupling.hpp"

namespace ckpd {

namespace {

// The law named at n (`law`), or `fallback` (the global law for a pair, else the default).
std::string read_law(const CaseNode& n, ContactConstants& c, const std::string& fallback) {
  const auto v = n.optional("law");
  if (!v) return fallback;
  const std::string name = v->as_string();
  if (!find_law(name)) v->fail("a contact law: one of " + known_laws());
  c.law = name;
  return name;
}

// The parameters of law `name` given at n, each checked against what the law expects; a
// parameter of another law is an error that says which law takes it.
void read_law_parameters(const CaseNode& n, const std::string& name, ContactConstants& c) {
  const LawType& type = *find_law(name);
  for (const LawParameter& parameter : type.parameters) {
    const auto v = n.optional(parameter.key);
    if (!v) continue;
    std::vector<double> values;
    if (v->is_sequence() && parameter.max_values > 1) {
      values = v->as_doubles();
      if (values.empty() || values.size() > parameter.max_values) v->fail(parameter.expected);
    } else {
      values.push_back(v->as_double());
    }
    for (double x : values)
      if (!parameter.valid(x)) v->fail(parameter.expected);
    c.parameters[parameter.key] = values;
  }
  for (const auto& [other, other_type] : law_registry())
    for (const LawParameter& parameter : other_type.parameters)
      if (other != name && n.has(parameter.key) && !c.parameters.count(parameter.key))
        n.required(parameter.key)
            .fail("no `" + parameter.key + "` here: it is a parameter of contact law `" + other +
                  "`, and the law here is `" + name + "` (set `law`)");
}

ContactConstants read_constants(const CaseNode& n, const std::string& fallback_law) {
  ContactConstants c;
  if (auto v = n.optional("radius")) c.radius = v->as_in_range(1e-9, 1e6, "a contact radius in m");
  if (auto v = n.optional("stiffness"))
    c.stiffness = v->as_in_range(1e-3, 1e16, "a contact stiffness in Pa");
  if (auto v = n.optional("skin")) c.skin = v->as_non_negative();
  if (auto v = n.optional("horizon"))
    c.horizon = v->as_in_range(1e-9, 1e6, "a contact horizon in m");
  read_law_parameters(n, read_law(n, c, fallback_law), c);
  return c;
}

// Every required parameter of the law in effect at n, there or (for a pair) globally.
void require_law_parameters(const CaseNode& n, const ContactConstants& here,
                            const ContactConstants* global) {
  const std::string name =
      here.law ? *here.law : (global && global->law ? *global->law : std::string(kDefaultLaw));
  for (const LawParameter& parameter : find_law(name)->parameters)
    if (parameter.required && !here.parameters.count(parameter.key) &&
        !(global && global->parameters.count(parameter.key)))
      n.fail("`" + parameter.key + "` for contact law `" + name + "` (" + parameter.expected + ")");
}

std::size_t body_index(const CaseNode& name_node, const Scene& scene) {
  const std::string name = name_node.as_string();
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].body.name == name) return b;
  name_node.fail("the name of a body in `bodies`");
}

void check_self_contact(const CaseNode& where, const SceneBody& sb) {
  if (sb.rigid)
    where.fail("a deformable body: rigid body '" + sb.body.name + "' has no self-contact");
}

}  // namespace

ContactSettings read_contact(const CaseNode& n, Scene& scene) {
  ContactSettings s;
  s.present = true;
  s.global = read_constants(n, kDefaultLaw);
  const std::string global_law = s.global.law.value_or(kDefaultLaw);
  if (auto list = n.optional("self_contact")) {
    for (const CaseNode& e : list->elements()) {
      const std::size_t b = body_index(e, scene);
      check_self_contact(e, scene.bodies[b]);
      s.self_contact.push_back(b);
    }
  }
  std::vector<CaseNode> pair_nodes;
  if (auto list = n.optional("pairs")) {
    for (const CaseNode& p : list->elements()) {
      const CaseNode names = p.required("bodies");
      const std::vector<CaseNode> two = names.elements();
      if (two.size() != 2) names.fail("a list of two body names");
      ContactPairSetting setting;
      setting.first = body_index(two[0], scene);
      setting.second = body_index(two[1], scene);
      if (setting.first > setting.second) std::swap(setting.first, setting.second);
      if (s.pair_setting(setting.first, setting.second))
        names.fail("a pair of bodies not listed before");
      setting.constants = read_constants(p, global_law);
      if (auto e = p.optional("enabled")) setting.enabled = e->as_bool();
      p.finish();
      const SceneBody& a = scene.bodies[setting.first];
      const SceneBody& b = scene.bodies[setting.second];
      if (setting.enabled) {
        if (setting.first == setting.second) check_self_contact(names, a);
        if (a.rigid && a.rigid->prescribed() && b.rigid && b.rigid->prescribed())
          names.fail("a pair that can interact: both bodies' motions are prescribed");
        const std::string law = setting.constants.law.value_or(global_law);
        if (find_law(law)->needs_stiffness && !setting.constants.stiffness && !s.global.stiffness)
          p.fail("a stiffness for this pair (or a global contact.stiffness)");
        require_law_parameters(p, setting.constants, &s.global);
      }
      s.pairs.push_back(setting);
      pair_nodes.push_back(p);
    }
  }
  n.finish();
  // The global law's parameters are needed when a pair without its own uses it with a stiffness
  // (or the law needs none).
  if (s.global.law) require_law_parameters(n, s.global, nullptr);

  // Every interacting pair must be resolvable: same dimension, a horizon for two rigid bodies.
  const std::vector<ContactBody> bodies = contact_bodies(std::as_const(scene));
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b) {
      const ContactPairSetting* own = s.pair_setting(a, b);
      const CaseNode& where = own ? pair_nodes[static_cast<std::size_t>(own - s.pairs.data())] : n;
      std::optional<PairLaw> law;
      try {
        law = s.law(bodies, a, b);
      } catch (const std::invalid_argument& e) {
        throw CaseError(where.where() + ": " + e.what());
      }
      const PointSet& A = bodies[a].points;
      const PointSet& B = bodies[b].points;
      if (law && A.dimension != B.dimension)
        throw CaseError(where.where() + ": contact between bodies of different dimensions: '" +
                        std::string(A.name) + "' is " + std::to_string(A.dimension) + "D, '" +
                        std::string(B.name) + "' is " + std::to_string(B.dimension) + "D");
    }
  return s;
}

}  // namespace ckpd
