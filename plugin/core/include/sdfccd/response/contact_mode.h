/// @file
/// @brief SdfccdContactMode: who answers the CCD's contacts (docs/bullet.md; the penalty mode is the paper's
/// Section 4.1, the solver mode is beyond the paper: docs/design/contact-response.md).
#pragma once

#include <cstdint>

namespace sdfccd {

/// Who turns the contacts of a pair into a response.
enum class SdfccdContactMode : std::uint8_t {
  Penalty,  ///< the paper's continuous (or discrete) penalty model: impulses from the contact integrals
  Solver,   ///< speculative manifold points answered by the host's constraint solver (Bullet's)
};

}  // namespace sdfccd
