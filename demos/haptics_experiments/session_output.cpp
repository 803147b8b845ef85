/// @file
/// @brief What the tool writes of a haptic session: the per-tick CSV and the summary JSON (see session_output.h).
#include "haptics_experiments/session_output.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/output_file.h"

namespace sdfccd::haptics {

void writeTickCsv(const std::string& path, const std::vector<HapticTickRecord>& ticks) {
  OutputFile file(path);
  std::ostream& out = file.stream();
  out << "tick,time,device_x,device_y,device_z,device_qw,device_qx,device_qy,device_qz,"
         "sim_x,sim_y,sim_z,sim_qw,sim_qx,sim_qy,sim_qz,force_x,force_y,force_z,torque_x,torque_y,torque_z,"
         "contacts,penetration,qp_state,sim_cycle_ms\n";
  out << std::setprecision(9);
  const auto pose = [&](const Rigid& r) {
    const Quat q(r.linear());
    out << r.translation().x() << ',' << r.translation().y() << ',' << r.translation().z() << ',' << q.w() << ','
        << q.x() << ',' << q.y() << ',' << q.z() << ',';
  };
  for (const HapticTickRecord& t : ticks) {
    out << t.tick << ',' << t.time << ',';
    pose(t.worldFromDevice);
    pose(t.worldFromSimulation);
    for (int i = 0; i < 6; ++i) out << t.wrenchOnDevice[i] << ',';
    out << t.contacts << ',' << t.penetration << ',' << t.qpState << ',' << t.simCycleMs << '\n';
  }
  file.commit();
}

namespace {

/// `text` as a JSON string literal (quotes, backslashes and control characters escaped).
std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

std::string summaryJson(const HapticSessionSummary& s) {
  std::ostringstream o;
  o << std::setprecision(9) << std::boolalpha;
  const auto num = [](double v) {
    std::ostringstream n;
    n << std::setprecision(9);
    if (std::isfinite(v))
      n << v;
    else
      n << "null";
    return n.str();
  };
  o << "{\n"
    << "  \"scene\": \"" << s.scene << "\",\n"
    << (s.sceneFile.empty() ? std::string() : "  \"scene_file\": " + jsonString(s.sceneFile) + ",\n")
    << "  \"method\": \"" << s.method << "\",\n"
    << "  \"real_time\": " << s.realTime << ",\n"
    << "  \"seconds\": " << num(s.seconds) << ",\n"
    << "  \"inserted\": " << (s.hasInsertCheck ? (s.inserted ? "true" : "false") : "null") << ",\n"
    << "  \"insert_progress\": " << num(s.insertProgress) << ",\n"
    << "  \"max_penetration_cells\": " << num(s.maxPenetrationCells) << ",\n"
    << "  \"tunneled\": " << (s.hasTunnelCheck ? (s.tunneled ? "true" : "false") : "null") << ",\n"
    << "  \"haptic_rate_hz\": " << num(s.hapticRateHz) << ",\n"
    << "  \"haptic_ticks\": " << s.hapticTicks << ",\n"
    << "  \"haptic_overruns\": " << s.hapticOverruns << ",\n"
    << "  \"haptic_jitter_p99_us\": " << num(s.hapticJitterP99Us) << ",\n"
    << "  \"sim_cycles\": " << s.simCycles << ",\n"
    << "  \"sim_cycle_p50_ms\": " << num(s.simCycleP50Ms) << ",\n"
    << "  \"sim_cycle_p99_ms\": " << num(s.simCycleP99Ms) << ",\n"
    << "  \"sim_cycle_max_ms\": " << num(s.simCycleMaxMs) << ",\n"
    << "  \"sim_cycle_cpu_p50_ms\": " << num(s.simCycleCpuP50Ms) << ",\n"
    << "  \"sim_cycle_cpu_p99_ms\": " << num(s.simCycleCpuP99Ms) << ",\n"
    << "  \"max_contacts\": " << s.maxContacts << ",\n"
    << "  \"mean_contacts\": " << num(s.meanContacts) << ",\n"
    << "  \"stuck_cycles\": " << s.stuckCycles << ",\n"
    << "  \"failed_cycles\": " << s.failedCycles << ",\n"
    << "  \"blocked_cycles\": " << s.blockedCycles << ",\n"
    << "  \"shell_points\": " << s.shellPoints << ",\n"
    << "  \"guard_stopped\": " << s.guardStopped << ",\n"
    << "  \"error\": " << (s.error.empty() ? std::string("null") : jsonString(s.error)) << ",\n"
    << "  \"real_time_priority\": " << jsonString(s.realTimePriority) << ",\n"
    << "  \"passivity\": " << s.passivityEnabled << ",\n"
    << "  \"port_energy_j\": " << num(s.passivity.energy) << ",\n"
    << "  \"port_energy_min_j\": " << num(s.passivity.minEnergy) << ",\n"
    << "  \"port_deficit_bound_j\": " << num(s.passivity.deficitBound) << ",\n"
    << "  \"passivity_controlled_ticks\": " << s.passivity.controlledTicks << ",\n"
    << "  \"rate_limited_ticks\": " << s.passivity.rateLimitedTicks << ",\n"
    << "  \"max_force_step_n\": " << num(s.passivity.maxForceStep) << ",\n"
    << "  \"colgate_max_stiffness\": " << num(s.colgateMaxStiffness) << ",\n"
    << "  \"runaway\": " << (s.runaway.empty() ? std::string("null") : jsonString(s.runaway)) << ",\n"
    << "  \"final_position\": [" << num(s.finalPosition.x()) << ", " << num(s.finalPosition.y()) << ", "
    << num(s.finalPosition.z()) << "]\n"
    << "}\n";
  return o.str();
}

}  // namespace sdfccd::haptics
