/// @file
/// @brief queryContacts(): the rigid CCD and the penalty model on one frame contract (Sections 3.3 and 4.1; see
/// contact_query.h), instantiated for every field type of field_interface.h.
#include "sdfccd/response/contact_query.h"

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/polytope_fields.h"

namespace sdfccd {

template <class Field>
void queryContacts(const PointTree& shellTree, const Field& field, const ShellMotion& shell,
                   const FieldMotion& fieldBody, double timestep, const ContactQuerySettings& settings,
                   ContactQueryResult& outResult, const ContactQueryClocks& clocks) {
  outResult.sdfFromShellStart = fieldBody.worldFromSdfStart.inverse() * shell.worldFromShellStart;
  outResult.sdfFromShellEnd = fieldBody.worldFromSdfEnd.inverse() * shell.worldFromShellEnd;
  outResult.penalty = PenaltyResult{};
  outResult.penaltyIntegrated = false;
  outResult.ccdSeconds = 0.0;
  outResult.penaltySeconds = 0.0;
  outResult.coefficients = PairResponseCoefficients{};

  const bool discrete = settings.penalty.model == PenaltyModel::Discrete;
  RigidCcdSettings ccd;
  ccd.sigma = settings.penalty.sigma;
  ccd.mode = discrete ? settings.discreteMode : CcdMode::AllIntervals;
  ccd.method = settings.method;
  ccd.octree = settings.octree;
  ccd.useTree = settings.useTree;
  ccd.threads = settings.threads;
  // The discrete model looks at the end pose only: a zero-length motion lists the points inside there.
  const Rigid& shellStartInSdf = discrete ? outResult.sdfFromShellEnd : outResult.sdfFromShellStart;
  // A query the history's certificates answer alone (no contact possible: most pairs of a pile, whose boxes
  // overlap) is not timed: it costs less than reading a thread CPU clock twice, which it would otherwise double.
  const bool certifiedClear =
      settings.coherence && rigidCcdCertifiedClear(shellTree, field, shellStartInSdf, outResult.sdfFromShellEnd, ccd,
                                                   *settings.coherence, outResult.ccd);
  double ccdEnd = 0.0;  // the CCD clock's last reading, when it ran
  if (!certifiedClear) {
    const double ccdStart = clocks.ccd ? clocks.ccd() : 0.0;
    if (settings.coherence) {
      rigidCcd(shellTree, field, shellStartInSdf, outResult.sdfFromShellEnd, ccd, *settings.coherence, outResult.ccd);
    } else {
      rigidCcd(shellTree, field, shellStartInSdf, outResult.sdfFromShellEnd, ccd, outResult.ccd);
    }
    if (clocks.ccd) {
      ccdEnd = clocks.ccd();
      outResult.ccdSeconds = ccdEnd - ccdStart;
    }
  }

  if (!settings.integratePenalty) return;
  const std::vector<Vec3>& pointsInShell = shellTree.shell().positions;
  if (outResult.ccd.contacts.empty()) {
    checkPenaltyInput(pointsInShell.size(), outResult.ccd, timestep, settings.penalty);
    return;
  }
  // On the same clock the penalty's time starts where the CCD's ended (a clock read less per touching role).
  const bool sameClock = !certifiedClear && clocks.penalty == clocks.ccd;
  const double penaltyStart = clocks.penalty ? (sameClock ? ccdEnd : clocks.penalty()) : 0.0;
  PenaltyRoleInput input;
  input.cellSize = settings.cellSize;
  input.anchors = settings.anchors;
  input.areas = &shellTree.shell().areas;
  if (settings.arbitrateNormals) input.curvatures = &shellTree.curvatures();
  outResult.penalty = integratePenaltyWithCoefficients(pointsInShell, field, outResult.ccd, shell, fieldBody, timestep,
                                                       settings.penalty, input, outResult.coefficients);
  outResult.penalty.stiffnessCapped = outResult.coefficients.stiffnessCapped;
  outResult.penaltyIntegrated = true;
  if (clocks.penalty) outResult.penaltySeconds = clocks.penalty() - penaltyStart;
}

#define SDFCCD_INSTANTIATE_CONTACT_QUERY(Field)                                                                      \
  template void queryContacts<Field>(const PointTree&, const Field&, const ShellMotion&, const FieldMotion&, double, \
                                     const ContactQuerySettings&, ContactQueryResult&, const ContactQueryClocks&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_CONTACT_QUERY)
SDFCCD_FOR_EACH_TRIANGLE_FIELD(SDFCCD_INSTANTIATE_CONTACT_QUERY)
#undef SDFCCD_INSTANTIATE_CONTACT_QUERY

}  // namespace sdfccd
