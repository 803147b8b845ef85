/// @file
/// @brief The session's fault-injection seam (internal to the haptics library; the tests reach it through the
/// library's source folder): a loop that throws at a chosen cycle or tick, to show that the session then ends with
/// summary.error set and the device rendering zero.
#pragma once

#include <cstdint>

#include "sdfccd/haptics/haptic_device.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/haptic_session.h"

namespace sdfccd::haptics {

/// Where a session throws (-1: never).
struct SessionFaults {
  std::int64_t simulationCycle = -1;  ///< constraint methods: the simulation cycle with this index
  std::int64_t hapticTick = -1;       ///< penalty methods: the haptic tick with this number (the step runs in it)
};

/// runHapticSession on the caller's device with `faults` injected.
HapticSessionResult runHapticSessionWithFaults(const HapticScene& scene, const HapticSessionSettings& settings,
                                               HapticDevice& device, const SessionFaults& faults);

}  // namespace sdfccd::haptics
