#pragma once
// HydroShoot's grapevine digitizing tables (docs/plants.md, "HydroShoot's digitizing tables"):
// `Souche;tronc;element;sarment;rameau;rang;X;Y;Z[;Diam]`, one row per digitized point (the top of
// an internode, in cm), read into the multiscale tree HydroShoot's `vine_mtg` builds from the same
// file (openalea/hydroshoot, architecture.py) — the same vertices in the same order, with the same
// labels, scales, complexes, parents and edges — so that `importMtgPlant` draws it as it draws an
// MTG archive:
//
// - scale 1 the plant (`plant<Souche>`), scale 2 its perennial axes (`trunk`, then `arm<tronc>`
//   branching from the trunk) and its shoots (`shI<rameau>`, `GI<rameau>` for a G shoot or one on
//   a pruning complex, `shII<k>`… for secondary ones), scale 3 the digitized entities;
// - `element`: an internode of the perennial axis (`inT<element>`: `<` after the one before, the
//   first of an arm `+` from the trunk's last) or, with a dot (`8.A`, `9.A.3`), a pruning complex
//   (`cx<element>`, `+` from the internode, or from the complex it refines);
// - `sarment` (not 0): an internode of a three-year-old cane (`inT3y<sarment>`), `<` after the
//   one before while the integer part stays, else `+` from the complex or the internode;
// - `rameau` (not 0) with `rang` 0: a spur's two-year-old internode (`inT2y<rameau>`), `rang` ≥ 1:
//   the shoot's internodes (`inI<rang>`, the first `+` with a new shoot complex); `a.b_c` a
//   secondary shoot of order c on internode b of the current shoot (`inII<rang>`, `inIII`… for
//   deeper orders);
// - X Y Z rounded to 0.01 as vine_mtg rounds them, `Diam` the internode's top diameter.
//
// Labels are what vine_mtg writes, pandas' reading of each column included (a column of decimals
// is read as floats: `sarment` 1 in a column that also holds 1.2 is "1.0"). Where vine_mtg fails
// (an assertion, a Python error) this reader refuses in words naming the file, the line and what
// to do. Petiole and leaf rows (p, f or l in `rameau`) are read past and counted in `notes`.
#include <filesystem>
#include <string>
#include <string_view>

#include "leafdig/model/archive/mtg_archive.hpp"

namespace leafdig::model {

// Whether a text reads as a HydroShoot digitizing table: its first line is nine or ten fields
// separated by ';' (the header).
[[nodiscard]] bool looksLikeHydroShootTable(std::string_view text);

// The table's tree, with features XX YY ZZ TopDiameter. InputError naming the source and line.
[[nodiscard]] MtgArchive parseHydroShootTable(std::string_view text, const std::string& source);
[[nodiscard]] MtgArchive readHydroShootTable(const std::filesystem::path& path);

}  // namespace leafdig::model
