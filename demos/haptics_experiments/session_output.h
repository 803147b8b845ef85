/// @file
/// @brief What the tool writes of a haptic session: the per-tick CSV and the summary JSON (the `haptics` command's
/// ticks.csv and summary.json; the tests read them too).
#pragma once

#include <string>
#include <vector>

#include "sdfccd/haptics/haptic_session.h"

namespace sdfccd::haptics {

/// Writes the per-tick CSV (atomically).
void writeTickCsv(const std::string& path, const std::vector<HapticTickRecord>& ticks);
/// The summary as a JSON object text (keys in snake_case, as the CLI's summary.json).
std::string summaryJson(const HapticSessionSummary& summary);

}  // namespace sdfccd::haptics
