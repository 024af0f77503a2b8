// The curator's correction dialog, one for a leaf's review and a plant's (Plant view): the items
// offered (one, or a tree to choose from: each label's " · " parts are its levels), the stored
// position (x, y, z) or value of the one chosen to edit, and the reason, which the correction needs.
#pragma once

#include <QString>
#include <optional>
#include <vector>

#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/review.hpp"

class QWidget;

namespace leafdig::station {

struct CorrectionChoice {
  QString label;                 // "Node 3 · stem diameter 1 (17.10 mm)": levels of the tree; empty for a single item
  acquisition::Correction item;  // what, row, col, … and the stored position or value
};

// Shows the dialog (modal). The chosen item with the edited position or value and the reason
// (not who: the caller's curator), or nothing when cancelled. `valueName` names a value
// ("thickness", "diameter").
[[nodiscard]] std::optional<acquisition::Correction> askCorrection(QWidget* parent, const QString& title,
                                                                   const std::vector<CorrectionChoice>& choices,
                                                                   const QString& valueName);

// A correction's effect in words, as the curator confirms it (acquisition::previewCorrection):
// how far the point moves (first, as a warning, when further than `confirmAboveMm`), then each
// measure that changes, before → after with the change in per cent.
[[nodiscard]] QString effectText(const acquisition::CorrectionEffect& effect, double confirmAboveMm);
// Asks the curator whether to write the correction, showing its effect (modal; a move further
// than `confirmAboveMm` asks with a warning). True: write it.
[[nodiscard]] bool confirmCorrection(QWidget* parent, const acquisition::CorrectionEffect& effect,
                                     double confirmAboveMm);

}  // namespace leafdig::station
