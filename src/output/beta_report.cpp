#include "src/output/beta_report.hpp"

#include <sstream>

namespace ckpd {

std::string beta_setup_note(const Body& body) {
  if (!body.beta_cap) return "";
  std::ostringstream os;
  os << "body '" << body.name << "': beta capped at 1 on " << body.beta_capped_points << " of "
     << body.size() << " points (largest raw family volume / full family volume "
     << body.beta_max_raw << ")";
  return os.str();
}

nlohmann::ordered_json beta_summary(const Body& body) {
  return {{"policy", body.beta_cap ? "capped" : "strict"},
          {"capped_points", body.beta_capped_points},
          {"max_raw", body.beta_max_raw}};
}

}  // namespace ckpd
