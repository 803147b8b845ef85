/// @file
/// @brief Report section `protocol`: paper Fig. 10a under the paper's protocol beside ours —
/// the largest stable timestep of the continuous and the discrete penalty model with the penalty impulses applied
/// over the *next* step (the paper, Section 4.1) and in the *same* step (ours), the energy each trial gained, and
/// the one-degree-of-freedom prediction beside the measurement.
///
/// @details Setup as the `stability` section: assets/scenes/drop-bunnies.json (penalty mode, per-point
/// stiffness 10,000 N/m and damping 5 N s/m, shell-normal direction) without friction and without time-of-impact
/// clamping, symplectic Euler in Bullet, both models treated alike. Every timestep of the grid is run for every
/// model and timing (not only up to the first failure), so the energy gain is seen on both sides of the limit.
///
/// The 1-DOF model (docs/design/penalty-stability.md, "Force timing"): a linear spring in sustained contact,
/// h = omega dt, x_{n+1} - 2 x_n + x_{n-1} = -h^2 (the force's argument); the per-step amplification |z| is the
/// larger root modulus of each characteristic polynomial. omega is not known for a pile of bunnies (it depends on
/// how many points touch), so it is calibrated once from the measured limit of one model and timing (ours,
/// discrete: h = 2/sqrt(3)); the other limits are then predictions.
#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "bench/bullet_stability_search.h"
#include "cli/markdown_table.h"
#include "cli/report_registry.h"
#include "report/paper_figures.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {
namespace {

/// One model under one force timing, with its 1-DOF characteristic polynomial z^2 + b(h) z + c(h).
struct ProtocolVariant {
  const char* name;
  PenaltyModel model;
  ForceTiming timing;
  double extraDamping;  // N s/m per point replacing the scene's (0: the scene's)
  const char* polynomial;
  double (*b)(double h2);
  double (*c)(double h2);
  const char* limit;  // the 1-DOF stability bound on h, in words
  double hLimit;      // the bound (infinity: always stable; 0: never)
};

const ProtocolVariant kProtocolVariants[] = {
    {"continuous, next step (paper)", PenaltyModel::Continuous, ForceTiming::NextStep, 0.0,
     "z^2 + (h^2/2 - 2) z + (1 + h^2/2)", [](double h2) { return h2 / 2 - 2; }, [](double h2) { return 1 + h2 / 2; },
     "never (abs(z)^2 = 1 + h^2/2)", 0.0},
    {"discrete, next step (paper)", PenaltyModel::Discrete, ForceTiming::NextStep, 0.0, "z^2 - (2 - h^2) z + 1",
     [](double h2) { return h2 - 2; }, [](double) { return 1.0; }, "h < 2 (neutral: no decay)", 2.0},
    {"continuous, same step (ours)", PenaltyModel::Continuous, ForceTiming::SameStep, 0.0,
     "z^2 + (3h^2/2 - 2) z + (1 - h^2/2)", [](double h2) { return 1.5 * h2 - 2; }, [](double h2) { return 1 - h2 / 2; },
     "h < sqrt(2) = 1.414", std::sqrt(2.0)},
    {"discrete, same step (ours)", PenaltyModel::Discrete, ForceTiming::SameStep, 0.0, "z^2 + (2h^2 - 2) z + (1 - h^2)",
     [](double h2) { return 2 * h2 - 2; }, [](double h2) { return 1 - h2; }, "h < 2/sqrt(3) = 1.155",
     2.0 / std::sqrt(3.0)},
};
constexpr int kCalibration = 3;  // the variant whose measured limit calibrates omega

/// The larger root modulus of z^2 + b z + c: the 1-DOF amplification per step.
double amplification(const ProtocolVariant& v, double h) {
  const double h2 = h * h;
  const double b = v.b(h2), c = v.c(h2);
  const std::complex<double> root = std::sqrt(std::complex<double>(b * b - 4 * c, 0.0));
  return std::max(std::abs((-b + root) / 2.0), std::abs((-b - root) / 2.0));
}

/// A trial's energy gain as a table cell: "+12.3 J" (stable), "> +40 J NaN/energy gain/tunnelled" (unstable).
std::string gainCell(const StabilityTrial& t) {
  if (t.stable) return fmt("%+.2f J ok", t.maxEnergyGain);
  return fmt("> %+.1f J **%s**", t.maxEnergyGain, t.why.c_str());
}

/// The largest timestep of `trials` before the first unstable one (0: none).
double largestBeforeFailure(const std::vector<StabilityTrial>& trials) {
  double largest = 0.0;
  for (const StabilityTrial& t : trials) {
    if (!t.stable) break;
    largest = t.timestep;
  }
  return largest;
}

std::string ms(double seconds) {
  return seconds > 0 ? fmt("%.2f ms", 1e3 * seconds) : std::string("none");
}

ReportSection runProtocol(const ReportContext& ctx) {
  Scene scene = loadScene((ctx.assetsDir / "scenes" / "drop-bunnies.json").string());
  scene.effects.erase("friction");
  scene.contact.direction = PenaltyDirection::ShellNormal;  // the paper's force direction
  if (ctx.smoke) scene.bodies.resize(4);
  StabilityTrialSettings base;
  base.cacheDir = ctx.cacheDir.string();
  base.stiffness = scene.contact.stiffness;
  base.duration = ctx.smoke ? 0.3 : (ctx.quick ? 0.8 : 1.5);
  const std::vector<double> timesteps =
      ctx.smoke
          ? std::vector<double>{0.001, 0.002, 0.004}
          : (ctx.quick ? std::vector<double>{0.0005, 0.001, 0.0015, 0.002, 0.003, 0.004}
                       : std::vector<double>{0.0005, 0.00075, 0.001, 0.00125, 0.0015, 0.002, 0.0025, 0.003, 0.004});
  // With more damping (25 N s/m per point instead of 5) the paper's timing is run again: the lag's energy gain
  // must be absorbed by damping (zeta >~ h/4), which is where a 3x can come from. Not in smoke runs.
  const double strongDamping = 25.0;
  const int variantCount = 4;
  const int dampedCount = ctx.smoke ? 0 : 2;
  std::vector<std::vector<StabilityTrial>> trials(std::size_t(variantCount + dampedCount));
  const double total = double(trials.size() * timesteps.size());
  double done = 0.0;
  for (int v = 0; v < variantCount + dampedCount; ++v) {
    const ProtocolVariant& variant = kProtocolVariants[v < variantCount ? v : v - variantCount];
    Scene s = scene;
    if (v >= variantCount) s.contact.damping = strongDamping;
    StabilityTrialSettings settings = base;
    settings.model = variant.model;
    settings.forceTiming = variant.timing;
    for (const double dt : timesteps) {
      settings.timestep = dt;
      trials[std::size_t(v)].push_back(runStabilityTrial(s, settings));
      ctx.progress(++done / total);
    }
  }
  auto variantName = [&](int v) {
    return v < variantCount
               ? std::string(kProtocolVariants[v].name)
               : std::string(kProtocolVariants[v - variantCount].name) + fmt(", damping %.0f", strongDamping);
  };
  {
    OutputFile csv(ctx.outDir / "protocol_trials.csv");
    csv.stream() << "variant,timestep_s,stable,max_energy_gain_j,max_penetration_cells,why\n";
    for (int v = 0; v < int(trials.size()); ++v) {
      for (const StabilityTrial& t : trials[std::size_t(v)]) {
        csv.stream() << '"' << variantName(v) << "\"," << t.timestep << ',' << (t.stable ? 1 : 0) << ','
                     << t.maxEnergyGain << ',' << t.maxPenetrationCells << ',' << (t.why.empty() ? "-" : t.why) << '\n';
      }
    }
    csv.commit();
  }

  double largest[6] = {0, 0, 0, 0, 0, 0};
  for (int v = 0; v < int(trials.size()); ++v) largest[v] = largestBeforeFailure(trials[std::size_t(v)]);
  // omega from the calibration variant's measured limit, h_limit = omega dt_limit: only when that variant failed
  // inside the grid (else its limit is unknown). The limit lies between the last stable and the first unstable dt;
  // the last stable one is taken, so omega is an upper estimate.
  const bool calibrated = largest[kCalibration] > 0 && largest[kCalibration] < timesteps.back();
  const double omega = calibrated ? kProtocolVariants[kCalibration].hLimit / largest[kCalibration] : NAN;

  std::string md = "## Fig. 10a under the paper's protocol beside ours (force timing)\n\n";
  md +=
      fmt("%zu bunnies (`drop-bunnies.json`: penalty mode, %.0f N/m and %.0f N s/m per point, shell-normal direction) "
          "without friction and without time-of-impact clamping, symplectic Euler in Bullet, %.1f s per trial. "
          "**next step** (the paper, Section 4.1): the impulses integrated over a step's motion act over the next "
          "step; **same step** (ours): they are integrated over the step's predicted motion and applied before Bullet "
          "integrates it. Both models are treated alike in each timing. Criterion: %s. Every timestep is run; the "
          "largest stable timestep is the last one before the first failure.\n\n",
          scene.bodies.size(), base.stiffness, scene.contact.damping, base.duration, kStabilityCriterion);
  std::vector<std::string> header = {"dt (ms)"};
  for (int v = 0; v < int(trials.size()); ++v) header.push_back(variantName(v));
  MarkdownTable gains(header);
  for (std::size_t i = 0; i < timesteps.size(); ++i) {
    std::vector<std::string> row = {fmt("%g", 1e3 * timesteps[i])};
    for (const auto& t : trials) row.push_back(gainCell(t[i]));
    gains.addRow(row);
  }
  md +=
      "**Measured: largest rise of the total energy above its start** (an unstable trial stops at the breach, "
      "so its figure is a lower bound):\n\n" +
      gains.str() + "\n";

  MarkdownTable limits({"model, timing", "1-DOF characteristic polynomial", "1-DOF stable for", "predicted dt limit",
                        "measured largest stable dt"});
  for (int v = 0; v < variantCount; ++v) {
    const ProtocolVariant& variant = kProtocolVariants[v];
    std::string predicted = "n/a";
    if (std::isfinite(omega)) {
      predicted = variant.hLimit > 0 ? fmt("%.2f ms", 1e3 * variant.hLimit / omega) : std::string("none");
      if (v == kCalibration) predicted += " (calibrates omega)";
    }
    limits.addRow({variant.name, variant.polynomial, variant.limit, predicted, ms(largest[v])});
  }
  for (int v = variantCount; v < int(trials.size()); ++v) {
    limits.addRow({variantName(v), "(damped)", "zeta >~ h/4 needed for the continuous model", "-", ms(largest[v])});
  }
  md += (calibrated ? fmt("**Limits: the 1-DOF prediction beside the measurement** (h = omega dt; omega = %.0f 1/s "
                          "calibrated from the measured limit of the discrete model with our timing):\n\n",
                          omega)
                    : std::string("**Limits: the 1-DOF bounds beside the measurement** (omega not calibrated: the "
                                  "discrete model with our timing did not fail inside the grid):\n\n")) +
        limits.str() + "\n";

  MarkdownTable amp({"dt (ms)", "h", kProtocolVariants[0].name, kProtocolVariants[1].name, kProtocolVariants[2].name,
                     kProtocolVariants[3].name});
  if (std::isfinite(omega)) {
    for (const double dt : timesteps) {
      const double h = omega * dt;
      amp.addRow({fmt("%g", 1e3 * dt), fmt("%.2f", h), fmt("%.3f", amplification(kProtocolVariants[0], h)),
                  fmt("%.3f", amplification(kProtocolVariants[1], h)),
                  fmt("%.3f", amplification(kProtocolVariants[2], h)),
                  fmt("%.3f", amplification(kProtocolVariants[3], h))});
    }
    md +=
        "**1-DOF amplification per step |z|** at the same h (> 1: energy grows; the unilateral contact clips "
        "the oscillation, so a pile gains less than this):\n\n" +
        amp.str() + "\n";
  }

  auto ratio = [](double a, double b) {
    if (!(b > 0)) return std::string("n/a (discrete never stable)");
    return a > 0 ? fmt("%.2fx", a / b) : std::string("0 (continuous stable at no dt of the grid)");
  };
  md += fmt(
      "**Ratio continuous / discrete of the largest stable timestep:** paper's timing %s, ours %s%s (paper: %.0fx). "
      "1-DOF: with the paper's timing the continuous model's force lags the motion by half a step and gains energy "
      "at every step unless damped (|z|^2 = 1 + h^2/2), so under an energy criterion it cannot be 3x more stable; "
      "with our timing both models are semi-implicit and the ratio is sqrt(2) / (2/sqrt(3)) = 1.22 in sustained "
      "contact. The paper's 3x is an impact (visual) criterion with damping that absorbs the lag.\n\n",
      ratio(largest[0], largest[1]).c_str(), ratio(largest[2], largest[3]).c_str(),
      dampedCount > 0
          ? fmt(", paper's timing with damping %.0f %s", strongDamping, ratio(largest[4], largest[5]).c_str()).c_str()
          : "",
      kPaperTimestepRatio);
  md += "Every trial: `protocol_trials.csv`.\n";

  ReportSection section;
  // The stated expectation (docs/design/penalty-stability.md): under our timing the continuous model is at least as
  // stable.
  section.ok = largest[2] >= largest[3] && largest[3] > 0;
  section.markdown = md;
  return section;
}

const ReportRegistrar bullet_fig10a_protocolRegistrar(31, "protocol", "Fig. 10a under the paper's protocol beside ours",
                                                      runProtocol);

}  // namespace
}  // namespace sdfccd::cli
