/// @file
/// @brief ContactLoads: contact mass scaling of the per-area penalty law. Each dynamic body's contact load (the
/// stiffness and damping its contacts put on it) of the last step sets the mass it moves with while in contact;
/// this step's roles add up the next step's.
#pragma once

#include <cstddef>
#include <unordered_map>

#include "sdfccd/response/contact_material.h"

class btCollisionObject;

namespace sdfccd::bullet::detail {

struct BodyStep;
class BodySteps;
struct ContactRecord;

class ContactLoads {
 public:
  /// Scales a dynamic body's mass for the contact response by last step's contact load (see the definition).
  void applyContactMass(BodyStep& step, double timeStep, const StabilityCapSettings& caps) const;
  /// Adds this role's stiffness and damping (`coefficients`) to its bodies' next load.
  void add(const ContactRecord& record, double roleScale, const PairResponseCoefficients& coefficients,
           const BodySteps& bodies);
  /// After the step's response: this step's loads become the ones read by the next step.
  void endStep(std::size_t bodyCount);

 private:
  /// A body's contact load of one step.
  struct Load {
    double stiffness = 0.0;  ///< N/m, over its pairs; a pair of two dynamic bodies counts twice (Gershgorin)
    double damping = 0.0;    ///< N s/m, over its pairs
  };
  std::unordered_map<const btCollisionObject*, Load> m_loads, m_nextLoads;  // last step's (read), this step's
};

}  // namespace sdfccd::bullet::detail
