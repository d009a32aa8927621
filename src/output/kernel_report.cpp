#include "src/output/kernel_report.hpp"

#include <sstream>
#include <string>

#include "bodies/force_model.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/state_based_model.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

namespace {

// A CKPD body: the default table, or one of the CKPD model's other instantiations.
bool is_ckpd(const Body& body) {
  return body.model == nullptr || std::string(force_model(body).name) == "ckpd";
}

// Why a body takes the general path.
std::string general_reason(const Body& body) {
  if (body.stencil) return "bond-only body: the stencil does not pay";
  return "no stencil: " + body.stencil_note;
}

}  // namespace

std::string kernel_path_note(const Body& body) {
  std::ostringstream os;
  os << force_model(body).name << " model";
  if (body.model == &state_based_kernels())
    os << " (strain measure m = " << body.state_based.m << ")";
  else if (is_ckpd(body))
    os << " (strain measure m = " << body.strain_measure << ", force form "
       << to_string(body.force_form) << ")";
  os << ", ";
  if (uses_lattice_stencil(body)) {
    const LatticeStencil& st = *body.stencil;
    os << "lattice stencil (" << st.slots << " offsets, " << st.pairs << " pairs, " << st.triples
       << " triples, " << static_cast<double>(st.bytes()) / 1e6 << " MB)";
  } else {
    os << "general path (" << general_reason(body);
    if (body.upper_rows)
      os << "; adjacency rows " << static_cast<double>(body.upper_rows->bytes()) / 1e6 << " MB";
    os << ")";
  }
  return os.str();
}

nlohmann::ordered_json kernel_path_summary(const Body& body) {
  const char* model = force_model(body).name;
  nlohmann::ordered_json j;
  if (uses_lattice_stencil(body))
    j = {{"model", model}, {"path", "stencil"}, {"stencil_bytes", body.stencil->bytes()}};
  else
    j = {{"model", model},
         {"path", "general"},
         {"note", general_reason(body)},
         {"adjacency_rows_bytes", body.upper_rows ? body.upper_rows->bytes() : 0}};
  // CKPD bodies (the default law and the Seth-Hill one, either force form) report their strain
  // measure and force form; state-based bodies their strain measure.
  if (body.model == &state_based_kernels()) {
    j["strain_measure"] = {{"m", body.state_based.m}};
  } else if (is_ckpd(body)) {
    j["strain_measure"] = {{"m", body.strain_measure}};
    j["force_form"] = to_string(body.force_form);
  }
  return j;
}

}  // namespace ckpd
