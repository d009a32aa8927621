// The keys of `contact` and its pairs in the key table (src/input/key_table.hpp), with one
// variant per contact law of contact/laws/ holding that law's parameters.
#include "contact/dem_law.hpp"
#include "src/input/key_table.hpp"

namespace ckpd {

namespace {

using K = ValueKind;

std::vector<KeySpec> constant_keys() {
  return {{"radius",
           K::number,
           "m",
           "0.75 x the larger spacing of the pair",
           "the contact radius l_c",
           {},
           "1e-9 to 1e6"},
          {"stiffness",
           K::number,
           "Pa",
           "none (a law that needs one then has no contact)",
           "the contact stiffness Ccon",
           {},
           "1e-3 to 1e16"},
          {"skin", K::number, "m", "the radius", "the broad phase's skin", {}, ">= 0"},
          {"horizon",
           K::number,
           "m",
           "each receiving body's own",
           "the horizon delta of the contact force (needed between two rigid bodies)",
           {},
           "1e-9 to 1e6"}};
}

KeySpec restitution_key() {
  return {"restitution", K::number, "-", kRequired, "the coefficient of restitution e", {},
          "(0, 1]"};
}
KeySpec friction_key() {
  return {"friction", K::number, "-", "0", "the Coulomb friction coefficient mu", {}, ">= 0"};
}

// The laws' parameters, as contact/laws/ registers them (a test checks the two agree).
std::vector<KeyVariant> law_variants() {
  return {{"repulsive",
           "the bond-based repulsion c (l_c - r) V^i V^j with one pair coefficient c, the "
           "harmonic mean of the two bodies' 9 Ccon / (pi delta^5); no friction",
           {}},
          {"repulsive_own_horizon",
           "the reference paper's rule: each side its own body's 9 Ccon / (pi delta^5); "
           "conserves neither momentum nor energy between bodies of different horizons",
           {}},
          {"linear_dashpot",
           "a linear spring k = c V^i V^j with a dashpot from e, a linear tangential spring and "
           "Coulomb friction",
           {restitution_key(),
            friction_key(),
            {"tangential_stiffness_ratio", K::number, "-", "2/7", "k_t / k_n", {}, "> 0"}}},
          {"hertz_mindlin",
           "Hertz normal and Mindlin tangential stiffness from E and nu, damping from e, Coulomb "
           "friction",
           {restitution_key(),
            friction_key(),
            {"youngs_modulus",
             K::number_or_pair,
             "Pa",
             "the bodies' own",
             "E: one value, or one per side of the pair",
             {},
             "> 0"},
            {"poisson_ratio",
             K::number_or_pair,
             "-",
             "the bodies' own",
             "nu: one value, or one per side of the pair",
             {},
             "(-1, 0.5)"},
            {"effective_radius",
             K::number,
             "m",
             "l_c / 4 (l_c against a wall)",
             "the effective radius R*",
             {},
             "> 0"}}}};
}

KeySection contact_section() {
  KeySection s{"contact", "contact",
               "Contact between the bodies' points (and a mesh wall's triangles). The settings "
               "here hold for every pair that `pairs` does not set otherwise. The law's "
               "parameters are keys next to `law`.",
               constant_keys()};
  s.keys.push_back({"law", K::text, "-", kDefaultLaw, "the contact law"});
  s.keys.push_back({"self_contact", K::names, "-", "none",
                    "the deformable bodies whose points also touch each other"});
  s.keys.push_back({"pairs",
                    K::sections,
                    "-",
                    "none",
                    "settings for single pairs of bodies",
                    {},
                    "",
                    "contact_pair"});
  s.discriminator = "law";
  s.default_variant = kDefaultLaw;
  s.variants = law_variants();
  return s;
}

KeySection pair_section() {
  KeySection s{"contact_pair",
               "contact.pairs entries",
               "The settings of one pair of bodies; what a pair leaves out comes from `contact`. A "
               "pair without a `law` of its own takes the parameters of the law it inherits.",
               {{"bodies", K::names, "-", kRequired,
                 "the two bodies' names (the same twice: "
                 "self-contact)"},
                {"enabled", K::boolean, "-", "true", "false: the pair never interacts"}}};
  for (KeySpec& k : constant_keys()) {
    k.fallback = "contact's";
    s.keys.push_back(std::move(k));
  }
  s.keys.push_back({"law", K::text, "-", "contact's", "the pair's contact law"});
  s.discriminator = "law";
  s.variants_inherited = true;
  s.variants = law_variants();
  for (KeyVariant& v : s.variants)
    for (KeySpec& k : v.keys)
      k.fallback = k.required() ? "contact's (the law needs it)" : "contact's, else " + k.fallback;
  return s;
}

const bool contact_registered = register_key_section(contact_section());
const bool pair_registered = register_key_section(pair_section());

}  // namespace

}  // namespace ckpd
