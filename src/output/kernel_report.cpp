#include "src/output/kernel_report.hpp"

#include <sstream>

#include "bodies/force_model.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

namespace {

// Why a body takes the general path.
std::string general_reason(const Body& body) {
  if (body.stencil) return "bond-only body: the stencil does not pay";
  return "no stencil: " + body.stencil_note;
}

}  // namespace

std::string kernel_path_note(const Body& body) {
  std::ostringstream os;
  os << force_model(body).name << " model, ";
  if (uses_lattice_stencil(body)) {
    const LatticeStencil& st = *body.stencil;
    os << "lattice stencil (" << st.slots << " offsets, " << st.pairs << " pairs, " << st.triples
       << " triples, " << static_cast<double>(st.bytes()) / 1e6 << " MB)";
  } else {
    os << "general path (" << general_reason(body) << ")";
  }
  return os.str();
}

nlohmann::ordered_json kernel_path_summary(const Body& body) {
  const char* model = force_model(body).name;
  if (uses_lattice_stencil(body))
    return {{"model", model}, {"path", "stencil"}, {"stencil_bytes", body.stencil->bytes()}};
  return {{"model", model}, {"path", "general"}, {"note", general_reason(body)}};
}

}  // namespace ckpd
