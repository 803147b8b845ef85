/// @file
/// @brief Report section `integration`: the continuous penalty impulse (paper Section 4.1, eqs. 3-4) with N
/// midpoint subintervals per contact interval, N = 1..9, against a fine reference (N = 10,000) and, for a plane
/// with a translating body, against the closed form.
///
/// @details Random contact trajectories of one shell point on a rigid body that translates and turns during the
/// step (up to 0.5 rad), against three fields: an analytic sphere (phi curved along the segment), the same sphere
/// sampled on a 40^3 grid (trilinear: kinks at cell faces) and a plane with a body that only translates (phi
/// linear in t, so the midpoint rule is exact for every N: the closed-form check of the harness). Trajectories
/// are sorted by what the CCD reports: entering (starts outside, ends inside), leaving, grazing (in and out
/// within the step) and fully inside. Each is integrated by integratePenalty() exactly as the Bullet plugin
/// does it (stiffness 1000 N/m, torques on, no damping or friction). Errors are relative to the reference's
/// impulse (N s) and angular impulse about the body's centre of mass (N m s); times are thread CPU time per
/// contact on one core. Core only (no Bullet).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli/line_plot.h"
#include "cli/markdown_table.h"
#include "cli/report_registry.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/output_file.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/thread_cpu_time.h"

namespace sdfccd::cli {
namespace {

constexpr int kMaxSubintervals = 9;
constexpr int kReferenceSubintervals = 10000;
constexpr int kDefaultSubintervals = 5;  // PenaltySettings' default and the paper's
constexpr double kTimestep = 0.001;      // s

enum class Kind { Entering, Leaving, Grazing, Inside };
const char* kKindNames[] = {"entering", "leaving", "grazing", "fully inside"};

/// One point's step: the body's start and end poses, the point and its normal in the body frame.
struct Trajectory {
  ShellMotion body;
  Vec3 pointInBody = Vec3::Zero();
  Vec3 normalInBody = Vec3::UnitX();
  RigidCcdResult ccd;  // one contact, AllIntervals
  Kind kind = Kind::Entering;
};

/// Classifies the CCD answer; false when the point never touches.
template <class Field>
bool classify(const Field& field, Trajectory& t) {
  const Vec3 p0 = t.body.worldFromShellStart * t.pointInBody;
  const Vec3 p1 = t.body.worldFromShellEnd * t.pointInBody;
  SegmentCcdSettings settings;
  settings.mode = CcdMode::AllIntervals;
  SegmentCcdResult r;
  field.intersectSegment(p0, p1, settings, r);
  if (!r.hit() || r.intervals.empty()) return false;
  double width = 0.0;
  for (std::size_t i = 0; i < r.intervals.size(); ++i) width += r.intervals[i].end - r.intervals[i].begin;
  if (!(width > 1e-9)) return false;  // a touching instant carries no impulse
  const bool startsInside = r.state == SegmentState::StartsInside;
  const bool endsInside = field.distance(p1) <= 0.0;
  t.kind = startsInside ? (endsInside ? Kind::Inside : Kind::Leaving) : (endsInside ? Kind::Entering : Kind::Grazing);
  PointContact contact;
  contact.point = 0;
  contact.state = r.state;
  contact.fraction = r.fraction;
  contact.intervals = r.intervals;
  contact.depthAtEnd = field.distance(p1);
  contact.pointNormalInShell = t.normalInBody;
  t.ccd.clear();
  t.ccd.contacts.push_back(contact);
  return true;
}

/// `perKind` trajectories of every kind near the unit sphere's surface (the plane: near y = 0). `turn`: the
/// body rotates by up to 0.5 rad during the step.
template <class Field>
std::vector<Trajectory> makeTrajectories(const Field& field, bool plane, bool turn, int perKind, unsigned seed) {
  const double pi = std::acos(-1.0);
  // A straight path crosses a plane once: no grazing contact there.
  const std::size_t kinds = plane ? 3 : 4;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto unit = [&]() {
    Vec3 v;
    do v = Vec3(u(rng), u(rng), u(rng));
    while (v.norm() < 0.1 || v.norm() > 1.0);
    return v.normalized();
  };
  std::array<int, 4> counts{0, 0, 0, 0};
  std::vector<Trajectory> out;
  for (long attempts = 0; attempts < 2000L * perKind && out.size() < kinds * static_cast<std::size_t>(perKind);
       ++attempts) {
    Trajectory t;
    t.pointInBody = 0.3 * unit();
    t.normalInBody = unit();
    const Quat start = Quat(Eigen::AngleAxisd(pi * u(rng), unit()));
    const Quat end = turn ? start * Quat(Eigen::AngleAxisd(0.5 * std::abs(u(rng)), unit())) : start;
    // The point starts near the surface and moves up to 0.6 (a fast step: a few tenths of the radius).
    const Vec3 p0 = plane ? Vec3(u(rng), 0.3 * u(rng), u(rng)) : (1.0 + 0.3 * u(rng)) * unit();
    const Vec3 p1 = p0 + 0.6 * std::abs(u(rng)) * unit();
    t.body.worldFromShellStart = Rigid::Identity();
    t.body.worldFromShellStart.linear() = start.toRotationMatrix();
    t.body.worldFromShellStart.translation() = p0 - start * t.pointInBody;
    t.body.worldFromShellEnd = Rigid::Identity();
    t.body.worldFromShellEnd.linear() = end.toRotationMatrix();
    t.body.worldFromShellEnd.translation() = p1 - end * t.pointInBody;
    if (!classify(field, t)) continue;
    int& count = counts[static_cast<std::size_t>(t.kind)];
    if (count >= perKind) continue;
    ++count;
    out.push_back(std::move(t));
  }
  return out;
}

PenaltySettings settingsWith(int subintervals) {
  PenaltySettings s;
  s.stiffness = 1000.0;
  s.damping = 0.0;
  s.enableDamping = false;
  s.enableRotation = true;
  s.subintervals = subintervals;
  return s;
}

template <class Field>
PenaltyResult integrate(const Field& field, const Trajectory& t, int subintervals) {
  const std::vector<Vec3> points{t.pointInBody};
  return integratePenalty(points, field, t.ccd, t.body, FieldMotion::fixed(Rigid::Identity()), kTimestep,
                          settingsWith(subintervals));
}

double relativeError(const Vec3& value, const Vec3& reference) {
  const double scale = reference.norm();
  return scale > 0.0 ? (value - reference).norm() / scale : (value.norm() > 0.0 ? 1.0 : 0.0);
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t i = std::min(values.size() - 1, static_cast<std::size_t>(q * static_cast<double>(values.size())));
  return values[i];
}

/// Errors and times of one field over N = 1..9.
struct FieldStudy {
  std::string name;
  std::size_t trajectories = 0;
  // [N-1][kind] relative errors of every trajectory of that kind
  std::vector<std::array<std::vector<double>, 4>> impulseErrors, angularErrors;
  std::vector<double> microsecondsPerContact;  // [N-1]
  double referenceMicroseconds = 0.0;
  double closedFormError = -1.0;  // the plane: largest relative error of the reference against the closed form
};

template <class Field>
FieldStudy study(const std::string& name, const Field& field, const std::vector<Trajectory>& trajectories,
                 bool closedForm, double minSeconds, const std::function<void(double)>& progress) {
  FieldStudy s;
  s.name = name;
  s.trajectories = trajectories.size();
  s.impulseErrors.resize(kMaxSubintervals);
  s.angularErrors.resize(kMaxSubintervals);
  std::vector<PenaltyResult> reference;
  reference.reserve(trajectories.size());
  const double referenceStart = threadCpuSeconds();
  for (const Trajectory& t : trajectories) reference.push_back(integrate(field, t, kReferenceSubintervals));
  s.referenceMicroseconds =
      1e6 * (threadCpuSeconds() - referenceStart) / static_cast<double>(std::max<std::size_t>(trajectories.size(), 1));
  if (closedForm) {
    // Plane, translating body: d(t) is linear, the normal and the handle constant, so the impulse is the width
    // of the interval times the force at its middle (and the angular impulse the handle cross it).
    s.closedFormError = 0.0;
    for (std::size_t i = 0; i < trajectories.size(); ++i) {
      const Trajectory& t = trajectories[i];
      const Vec3 p0 = t.body.worldFromShellStart * t.pointInBody;
      const Vec3 p1 = t.body.worldFromShellEnd * t.pointInBody;
      const Vec3 normal = t.body.worldFromShellStart.linear() * t.normalInBody;
      const Vec3 handle = p0 - t.body.worldFromShellStart.translation();
      Vec3 impulse = Vec3::Zero();
      for (std::size_t k = 0; k < t.ccd.contacts[0].intervals.size(); ++k) {
        const Interval& iv = t.ccd.contacts[0].intervals[k];
        const double middle = 0.5 * (iv.begin + iv.end);
        const double depth = field.distance(p0 + middle * (p1 - p0));
        impulse += 1000.0 * depth * (iv.end - iv.begin) * kTimestep * normal;  // on the shell: -k |d| N
      }
      s.closedFormError = std::max(s.closedFormError, relativeError(reference[i].impulseOnShell, impulse));
      s.closedFormError =
          std::max(s.closedFormError, relativeError(reference[i].angularImpulseOnShell, handle.cross(impulse)));
    }
  }
  for (int n = 1; n <= kMaxSubintervals; ++n) {
    std::vector<PenaltyResult> results;
    results.reserve(trajectories.size());
    for (const Trajectory& t : trajectories) results.push_back(integrate(field, t, n));
    // Timing: whole passes over the trajectories (the first one above warmed the caches) until at least
    // `minSeconds` of CPU time, so that a sub-microsecond evaluation is timed over many calls.
    long long evaluations = 0;
    double sink = 0.0;
    const double start = threadCpuSeconds();
    double elapsed = 0.0;
    do {
      for (const Trajectory& t : trajectories) sink += integrate(field, t, n).impulseOnShell.x();
      evaluations += static_cast<long long>(trajectories.size());
      elapsed = threadCpuSeconds() - start;
    } while (elapsed < minSeconds && !trajectories.empty());
    s.microsecondsPerContact.push_back(1e6 * elapsed / static_cast<double>(std::max<long long>(evaluations, 1)));
    if (std::isnan(sink)) s.microsecondsPerContact.back() = 0.0;  // keeps the loop from being optimized away
    for (std::size_t i = 0; i < trajectories.size(); ++i) {
      const std::size_t kind = static_cast<std::size_t>(trajectories[i].kind);
      s.impulseErrors[static_cast<std::size_t>(n - 1)][kind].push_back(
          relativeError(results[i].impulseOnShell, reference[i].impulseOnShell));
      s.angularErrors[static_cast<std::size_t>(n - 1)][kind].push_back(
          relativeError(results[i].angularImpulseOnShell, reference[i].angularImpulseOnShell));
    }
    progress(static_cast<double>(n) / kMaxSubintervals);
  }
  return s;
}

std::vector<double> allKinds(const std::array<std::vector<double>, 4>& byKind) {
  std::vector<double> all;
  for (const auto& v : byKind) all.insert(all.end(), v.begin(), v.end());
  return all;
}

/// A SphereField sampled on a grid of `cells`^3 cells over [-2.2, 2.2]^3 (every trajectory stays inside).
std::shared_ptr<const SdfGrid> sampledSphere(const SphereField& sphere, int cells) {
  const int n = cells + 1;
  const double spacing = 4.4 / cells;
  const Vec3 origin = Vec3::Constant(-2.2);
  std::vector<float> values;
  values.reserve(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        values.push_back(static_cast<float>(sphere.distance(origin + spacing * Vec3(i, j, k))));
  return std::make_shared<const SdfGrid>(Vec3i(n, n, n), origin, spacing, std::move(values));
}

ReportSection runIntegrationSection(const ReportContext& context) {
  const int perKind = context.smoke ? 100 : context.quick ? 500 : 3000;
  const double minSeconds = context.smoke ? 0.02 : context.quick ? 0.1 : 0.5;  // timing per N and field
  const SphereField sphere(Vec3::Zero(), 1.0);
  const GridField gridSphere(sampledSphere(sphere, 40));
  const PlaneField plane = PlaneField::ground();
  auto part = [&](int index) { return [&context, index](double f) { context.progress((index + f) / 3.0); }; };
  std::vector<FieldStudy> studies;
  studies.push_back(study("sphere (analytic)", sphere, makeTrajectories(sphere, false, true, perKind, 1), false,
                          minSeconds, part(0)));
  studies.push_back(study("sphere on a 40^3 grid", gridSphere, makeTrajectories(gridSphere, false, true, perKind, 2),
                          false, minSeconds, part(1)));
  studies.push_back(study("plane, translating body", plane, makeTrajectories(plane, true, false, perKind, 3), true,
                          minSeconds, part(2)));

  // Tables, CSV, plots.
  std::ostringstream csv;
  csv << "field,kind,subintervals,trajectories,impulse_error_median,impulse_error_p95,impulse_error_max,"
         "angular_error_median,angular_error_p95,angular_error_max,us_per_contact\n";
  std::ostringstream byN;
  byN << "| N | Impulse error, median | 95th pct. | max | Angular impulse error, median | 95th pct. | Time per "
         "contact (us) | Time / time at N = 1 |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  LinePlot errorPlot;
  errorPlot.title = "Penalty impulse: midpoint rule with N subintervals vs N = 10,000";
  errorPlot.xLabel = "N (midpoint subintervals per contact interval)";
  errorPlot.yLabel = "relative error";
  errorPlot.logY = true;
  LinePlot timePlot;
  timePlot.title = "Penalty impulse: time per contact vs N (one core)";
  timePlot.xLabel = "N (midpoint subintervals per contact interval)";
  timePlot.yLabel = "us per contact";
  const FieldStudy& main = studies[0];
  bool ok = true;
  std::string findings;
  for (const FieldStudy& s : studies) {
    PlotSeries impulse50{s.name + ": impulse, median", {}, {}};
    PlotSeries impulse95{s.name + ": impulse, 95th pct.", {}, {}};
    PlotSeries angular95{s.name + ": angular impulse, 95th pct.", {}, {}};
    PlotSeries time{s.name, {}, {}};
    for (int n = 1; n <= kMaxSubintervals; ++n) {
      const std::size_t i = static_cast<std::size_t>(n - 1);
      for (std::size_t kind = 0; kind <= 4; ++kind) {
        const std::vector<double> imp = kind < 4 ? s.impulseErrors[i][kind] : allKinds(s.impulseErrors[i]);
        const std::vector<double> ang = kind < 4 ? s.angularErrors[i][kind] : allKinds(s.angularErrors[i]);
        if (imp.empty()) continue;
        csv << '"' << s.name << "\"," << (kind < 4 ? kKindNames[kind] : "all") << ',' << n << ',' << imp.size() << ','
            << quantile(imp, 0.5) << ',' << quantile(imp, 0.95) << ',' << quantile(imp, 1.0) << ','
            << quantile(ang, 0.5) << ',' << quantile(ang, 0.95) << ',' << quantile(ang, 1.0) << ','
            << s.microsecondsPerContact[i] << '\n';
      }
      const std::vector<double> imp = allKinds(s.impulseErrors[i]);
      const std::vector<double> ang = allKinds(s.angularErrors[i]);
      // Log axis: an exact result (the plane) is drawn at 1e-16, double's rounding level.
      impulse50.x.push_back(n);
      impulse50.y.push_back(std::max(quantile(imp, 0.5), 1e-16));
      impulse95.x.push_back(n);
      impulse95.y.push_back(std::max(quantile(imp, 0.95), 1e-16));
      angular95.x.push_back(n);
      angular95.y.push_back(std::max(quantile(ang, 0.95), 1e-16));
      time.x.push_back(n);
      time.y.push_back(s.microsecondsPerContact[i]);
      if (&s == &main) {
        byN << "| " << n << (n == kDefaultSubintervals ? " (default)" : "") << " | " << fmt("%.2e", quantile(imp, 0.5))
            << " | " << fmt("%.2e", quantile(imp, 0.95)) << " | " << fmt("%.2e", quantile(imp, 1.0)) << " | "
            << fmt("%.2e", quantile(ang, 0.5)) << " | " << fmt("%.2e", quantile(ang, 0.95)) << " | "
            << fmt("%.3f", s.microsecondsPerContact[i]) << " | "
            << fmt("%.2f", s.microsecondsPerContact[i] / std::max(s.microsecondsPerContact[0], 1e-12)) << " |\n";
      }
    }
    // The plane is exact at every N (rounding level): the text states it, the plot would only squash the rest.
    if (s.closedFormError < 0.0) {
      errorPlot.series.push_back(impulse50);
      errorPlot.series.push_back(impulse95);
      if (&s == &main) errorPlot.series.push_back(angular95);
    }
    timePlot.series.push_back(time);
    // The error must fall from N = 1 to N = 9 on curved fields (midpoint: about 1/N^2).
    const double first = quantile(allKinds(s.impulseErrors[0]), 0.95);
    const double last = quantile(allKinds(s.impulseErrors[kMaxSubintervals - 1]), 0.95);
    if (s.closedFormError >= 0.0) {
      if (!(s.closedFormError < 1e-9) || !(last < 1e-9)) {
        ok = false;
        findings += "**The plane's closed form is not matched** (" + fmt("%.2e", s.closedFormError) + "). ";
      }
    } else if (!(last < first)) {
      ok = false;
      findings += "**The error of " + s.name + " does not fall with N.** ";
    }
  }

  std::ostringstream byKind;
  byKind << "| Field | Kind | Trajectories | Impulse error at N = 1, median / 95th pct. | at N = 5 | at N = 9 | "
            "Angular impulse at N = 5, median / 95th pct. |\n|---|---|---:|---:|---:|---:|---:|\n";
  for (const FieldStudy& s : studies) {
    for (std::size_t kind = 0; kind < 4; ++kind) {
      if (s.impulseErrors[0][kind].empty()) continue;
      auto cell = [&](const std::vector<std::array<std::vector<double>, 4>>& errors, int n) {
        const std::vector<double>& v = errors[static_cast<std::size_t>(n - 1)][kind];
        return fmt("%.1e", quantile(v, 0.5)) + " / " + fmt("%.1e", quantile(v, 0.95));
      };
      byKind << "| " << s.name << " | " << kKindNames[kind] << " | " << s.impulseErrors[0][kind].size() << " | "
             << cell(s.impulseErrors, 1) << " | " << cell(s.impulseErrors, kDefaultSubintervals) << " | "
             << cell(s.impulseErrors, kMaxSubintervals) << " | " << cell(s.angularErrors, kDefaultSubintervals)
             << " |\n";
    }
  }

  writeOutputFile((context.outDir / "integration_errors.csv").string(), csv.str());
  PlotSeries parabola{"1/(2 N^2): a parabolic depth profile (grazing)", {}, {}};
  for (int n = 1; n <= kMaxSubintervals; ++n) {
    parabola.x.push_back(n);
    parabola.y.push_back(0.5 / (n * n));
  }
  errorPlot.series.push_back(parabola);
  writeLinePlot(errorPlot, context.outDir / "integration_error.png");
  writeLinePlot(timePlot, context.outDir / "integration_time.png");

  const std::size_t d = kDefaultSubintervals - 1;
  const double default95 = quantile(allKinds(main.impulseErrors[d]), 0.95);
  const double one95 = quantile(allKinds(main.impulseErrors[0]), 0.95);
  const std::size_t grazing = static_cast<std::size_t>(Kind::Grazing);
  const double grazing1 = quantile(main.impulseErrors[0][grazing], 0.5);
  const double grazing5 = quantile(main.impulseErrors[d][grazing], 0.5);
  const double costRatio = main.microsecondsPerContact[d] / std::max(main.microsecondsPerContact[0], 1e-12);
  std::ostringstream md;
  md << "## Penalty integration: midpoint subintervals\n\n"
     << "The continuous penalty model integrates the force -k d(t) N(t) and its torque over each contact "
        "sub-interval of the step with the midpoint rule on N equal pieces (paper Section 4.1, eqs. 3-4; the paper "
        "uses N = 5, as does our default). Here one shell point on a body that moves and turns (up to 0.5 rad) "
        "during a 1 ms step meets a field; "
     << perKind
     << " trajectories of each kind (entering, leaving, grazing, fully inside) per field. Errors are relative to "
        "the same integral with N = 10,000; times are thread CPU time per contact on one core (they include the "
        "per-contact set-up, which does not depend on N).\n\n"
     << "### Unit sphere (analytic), all kinds\n\n"
     << byN.str() << "\n"
     << "### By kind of contact\n\n"
     << byKind.str() << "\n"
     << "The plane with a translating body is the closed-form check: d(t) is linear and N(t) constant, so the "
        "midpoint rule is exact for every N; the N = 10,000 reference matches the closed form to "
     << fmt("%.1e", studies[2].closedFormError)
     << " (relative). On the curved fields the error falls as 1/N^2. Grazing contacts are the hardest: the depth "
        "rises and falls within one interval, close to a parabola, for which the midpoint rule's relative error "
        "is exactly 1/(2 N^2) -- 0.5 at N = 1, 0.02 at N = 5; measured on the sphere: "
     << fmt("%.3f", grazing1) << " and " << fmt("%.4f", grazing5)
     << " (median). They set the 95th percentile of the first table. The 40^3 grid's kinks at cell faces change "
        "little.\n\n"
     << "**Default N = 5**: the 95th-percentile impulse error on the sphere is " << fmt("%.1e", default95)
     << " (N = 1: " << fmt("%.1e", one95) << "), for " << fmt("%.2f", costRatio) << "x the time of N = 1 per contact ("
     << fmt("%.3f", main.microsecondsPerContact[d]) << " vs " << fmt("%.3f", main.microsecondsPerContact[0])
     << " us). The integration is a small part of a contact's cost next to the CCD query that produced its "
        "intervals (section `segments`). The paper gives no error figure for N.\n\n"
     << findings << (findings.empty() ? "" : "\n\n")
     << "![Error vs N](integration_error.png)\n\n![Time vs N](integration_time.png)\n\n"
     << "Data: `integration_errors.csv`.\n";
  return {md.str(), ok};
}

const ReportRegistrar integrationRegistrar(40, "integration", "Penalty integration: midpoint subintervals",
                                           runIntegrationSection);

}  // namespace
}  // namespace sdfccd::cli
