#include "src/case/contact_loader.hpp"

#include <stdexcept>

#include "src/engine/contact_coupling.hpp"

namespace ckpd {

namespace {

ContactConstants read_constants(const CaseNode& n) {
  ContactConstants c;
  if (auto v = n.optional("radius")) c.radius = v->as_in_range(1e-9, 1e6, "a contact radius in m");
  if (auto v = n.optional("stiffness"))
    c.stiffness = v->as_in_range(1e-3, 1e16, "a contact stiffness in Pa");
  if (auto v = n.optional("skin")) c.skin = v->as_non_negative();
  if (auto v = n.optional("horizon"))
    c.horizon = v->as_in_range(1e-9, 1e6, "a contact horizon in m");
  return c;
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
  s.global = read_constants(n);
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
      setting.constants = read_constants(p);
      if (auto e = p.optional("enabled")) setting.enabled = e->as_bool();
      p.finish();
      const SceneBody& a = scene.bodies[setting.first];
      const SceneBody& b = scene.bodies[setting.second];
      if (setting.enabled) {
        if (setting.first == setting.second) check_self_contact(names, a);
        if (a.rigid && a.rigid->prescribed() && b.rigid && b.rigid->prescribed())
          names.fail("a pair that can interact: both bodies' motions are prescribed");
        if (!setting.constants.stiffness && !s.global.stiffness)
          p.fail("a stiffness for this pair (or a global contact.stiffness)");
      }
      s.pairs.push_back(setting);
      pair_nodes.push_back(p);
    }
  }
  n.finish();

  // Every interacting pair must be resolvable: same dimension, a horizon for two rigid bodies.
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b) {
      const ContactPairSetting* own = s.pair_setting(a, b);
      const CaseNode& where = own ? pair_nodes[static_cast<std::size_t>(own - s.pairs.data())] : n;
      std::optional<PairLaw> law;
      try {
        law = s.law(bodies, a, b);
      } catch (const std::invalid_argument& e) {
        throw CaseError(where.where() + ": " + e.what() +
                        ": give `horizon` for the pair or for all contact");
      }
      if (law && bodies[a].body->dimension != bodies[b].body->dimension)
        throw CaseError(where.where() + ": contact between bodies of different dimensions: '" +
                        bodies[a].body->name + "' is " + std::to_string(bodies[a].body->dimension) +
                        "D, '" + bodies[b].body->name + "' is " +
                        std::to_string(bodies[b].body->dimension) + "D");
    }
  return s;
}

}  // namespace ckpd
