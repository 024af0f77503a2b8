#include "leafdig/model/archive/plant_import.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "leafdig/model/archive/hydroshoot_table.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::model {

namespace {

// A length in whole metres for a message (however large: a wrong unit can make it anything).
std::string metres(double mm) {
  return std::to_string(static_cast<long long>(std::min(std::abs(mm) / 1000, 1e15)));
}

struct Pred {
  int vertex = -1;   // the entity whose point the base is
  int complex = -1;  // or the complex whose own coordinates it is
  char edge = '<';
};

class Importer {
 public:
  Importer(const MtgArchive& a, const ArchiveImportOptions& o) : a_(a), o_(o), n_(a.vertices.size()) {}

  ImportedPlant run() {
    ImportedPlant out;
    out.source = a_.source;
    out.vertices = n_;
    choosePlant(out);
    locate();
    out.plantVertices = static_cast<std::size_t>(std::count(inPlant_.begin(), inPlant_.end(), true));
    std::map<std::string, std::size_t> perClass;
    for (std::size_t v = 0; v < n_; ++v)
      if (inPlant_[v]) ++perClass[a_.vertices[v].symbol];
    out.perClass.assign(perClass.begin(), perClass.end());
    for (std::size_t v = 0; v < n_; ++v) {
      if (geometric_[v]) ++out.points;
      if (inPlant_[v] && !hasXyz_[v] && !below_[v]) ++out.withoutPoint;
    }
    if (out.points == 0)
      throw InputError(a_.source + ": plant " + out.plantLabel +
                       " has no entity with XX, YY and ZZ: leafdig draws a plant from its digitized coordinates");
    assignAxes(out);
    drawAxes(out);
    for (const MtgFeature& f : a_.features)
      if (!used(f.name)) out.notes.push_back("feature " + f.name + " is kept in the file, not drawn");
    out.notes.insert(out.notes.end(), a_.notes.begin(), a_.notes.end());
    std::set<std::string> keys;
    for (const std::string& k : o_.dressing.ignored)
      if (keys.insert(k).second) out.notes.push_back("dressing key " + k + " is read past");
    return out;
  }

 private:
  [[nodiscard]] static bool used(const std::string& name) {
    return name == "XX" || name == "YY" || name == "ZZ" || name == "TopDia" || name == "TopDiameter" ||
           name == "BottomDiameter";
  }
  [[nodiscard]] const MtgVertex& at(std::size_t v) const { return a_.vertices[v]; }
  [[nodiscard]] const MtgVertex& at(int v) const { return a_.vertices[static_cast<std::size_t>(v)]; }

  void choosePlant(ImportedPlant& out) {
    int seen = 0;
    for (std::size_t v = 1; v < n_ && plant_ < 0; ++v)
      if (at(v).scale == 1 && ++seen == o_.plant) plant_ = static_cast<int>(v);
    if (plant_ < 0) {
      int plants = 0;
      for (std::size_t v = 1; v < n_; ++v) plants += at(v).scale == 1 ? 1 : 0;
      throw InputError(a_.source + ": there is no plant " + std::to_string(o_.plant) + " (the file has " +
                       std::to_string(plants) + "): choose one of 1…" + std::to_string(std::max(plants, 1)));
    }
    out.plantLabel = at(plant_).label;
    out.plant.id = out.plantLabel;
  }

  // Which entities belong to the plant, which have coordinates, which are drawn as points.
  void locate() {
    const int xx = a_.feature("XX"), yy = a_.feature("YY"), zz = a_.feature("ZZ");
    inPlant_.assign(n_, false);
    hasXyz_.assign(n_, false);
    below_.assign(n_, false);
    geometric_.assign(n_, false);
    points_.assign(n_, Eigen::Vector3d::Zero());
    components_ = a_.components();
    const double scale = o_.mmPerUnit / o_.dressing.lengthUnit;
    for (std::size_t v = 1; v < n_; ++v) {
      // A complex is made before its components: one pass in order.
      inPlant_[v] =
          static_cast<int>(v) == plant_ || (at(v).complex >= 0 && inPlant_[static_cast<std::size_t>(at(v).complex)]);
      const auto x = a_.number(v, xx), y = a_.number(v, yy), z = a_.number(v, zz);
      if (inPlant_[v] && x && y && z) {
        hasXyz_[v] = true;
        points_[v] = Eigen::Vector3d(*x, *y, *z) * scale;
        if (!(points_[v].cwiseAbs().maxCoeff() <= kMaxArchiveCoordinateMm))
          throw InputError(a_.source + ", line " + std::to_string(at(v).line) + ": " + at(v).label + " lies " +
                           metres(points_[v].cwiseAbs().maxCoeff()) +
                           " m from the origin: are --units and the dressing file's LengthUnit right?");
      }
    }
    for (std::size_t v = n_; v-- > 1;)
      if ((hasXyz_[v] || below_[v]) && at(v).complex >= 0) below_[static_cast<std::size_t>(at(v).complex)] = true;
    for (std::size_t v = 1; v < n_; ++v) geometric_[v] = hasXyz_[v] && !below_[v];
    // The entity following each one on a '<' chain inside the same complex.
    follower_.assign(n_, -1);
    for (std::size_t v = 1; v < n_; ++v) {
      const MtgVertex& x = at(v);
      int from = -1;
      if (x.parent >= 0 && (x.edge == '<' || x.edge == 0)) from = x.parent;
      if (x.parent < 0 && x.after >= 0 && x.afterEdge == '<') from = x.after;
      if (from >= 0 && at(from).complex == x.complex && follower_[static_cast<std::size_t>(from)] < 0)
        follower_[static_cast<std::size_t>(from)] = static_cast<int>(v);
    }
    top_.assign(n_, -2);
  }

  // The point at the top of entity q: itself, or the top of its last component on the '<' chain
  // that has one; -1 when nothing below it has coordinates.
  int top(int q) {
    const auto u = static_cast<std::size_t>(q);
    if (top_[u] != -2) return top_[u];
    int result = -1;
    if (geometric_[u]) {
      result = q;
    } else if (below_[u] && !components_[u].empty()) {
      std::vector<int> chain{components_[u].front()};
      while (follower_[static_cast<std::size_t>(chain.back())] >= 0 && chain.size() <= n_)
        chain.push_back(follower_[static_cast<std::size_t>(chain.back())]);
      for (auto it = chain.rbegin(); it != chain.rend() && result < 0; ++it) result = top(*it);
    }
    top_[u] = result;
    return result;
  }

  // Where point g's base is: back through what it follows or branches from (entities without
  // coordinates passed over), or up to a complex whose own coordinates start the axis.
  Pred predOf(int g) {
    Pred p;
    int x = g;
    for (;;) {
      const MtgVertex& v = at(x);
      int q = -1;
      char e = '<';
      if (v.parent >= 0) {
        q = v.parent, e = v.edge == 0 ? '<' : v.edge;
      } else if (v.after >= 0) {
        q = v.after, e = v.afterEdge;
      } else {
        const int c = v.complex;
        if (c < 1 || !inPlant_[static_cast<std::size_t>(c)]) return p;
        if (hasXyz_[static_cast<std::size_t>(c)]) {
          p.complex = c;
          return p;
        }
        if (components_[static_cast<std::size_t>(c)].front() != x) return p;
        x = c;
        continue;
      }
      if (!inPlant_[static_cast<std::size_t>(q)]) return p;
      if (e == '+') p.edge = '+';
      const int t = top(q);
      if (t >= 0) {
        p.vertex = t;
        return p;
      }
      x = q;
    }
  }

  void assignAxes(ImportedPlant& out) {
    axisOf_.assign(n_, -1);
    for (std::size_t v = 1; v < n_; ++v) {
      if (!geometric_[v]) continue;
      const int g = static_cast<int>(v);
      const Pred p = predOf(g);
      if (p.vertex >= 0 && axisOf_[static_cast<std::size_t>(p.vertex)] >= 0) {
        const int bearer = axisOf_[static_cast<std::size_t>(p.vertex)];
        ImportedAxis& b = out.axes[static_cast<std::size_t>(bearer)];
        if (p.edge == '<' && b.vertices.back() == p.vertex) {
          b.vertices.push_back(g);
          axisOf_[v] = bearer;
          continue;
        }
        if (p.edge == '<') ++out.secondFollowers;
        ImportedAxis axis;
        axis.order = b.order + 1;
        axis.bearer = bearer + 1;
        axis.vertices.push_back(g);
        bases_.push_back(p);
        axisOf_[v] = static_cast<int>(out.axes.size());
        out.axes.push_back(std::move(axis));
        continue;
      }
      ImportedAxis axis;
      axis.vertices.push_back(g);
      bases_.push_back(p);
      axisOf_[v] = static_cast<int>(out.axes.size());
      out.axes.push_back(std::move(axis));
    }
  }

  [[nodiscard]] std::optional<double> diameter(int v, const char* name) const {
    const auto d = a_.number(static_cast<std::size_t>(v), a_.feature(name));
    if (!d) return std::nullopt;
    if (*d < 0)
      throw InputError(a_.source + ", line " + std::to_string(at(v).line) + ": " + name + " " +
                       a_.vertices[static_cast<std::size_t>(v)].cells[static_cast<std::size_t>(a_.feature(name))] +
                       " of " + at(v).label + " is below zero");
    const double mm = *d / o_.dressing.diameterUnit * o_.mmPerUnit;
    if (!(mm <= kMaxArchiveDiameterMm))
      throw InputError(a_.source + ", line " + std::to_string(at(v).line) + ": " + name + " of " + at(v).label +
                       " is " + metres(mm) + " m: are --units and the dressing file's DiameterUnit right?");
    return mm;
  }
  [[nodiscard]] std::optional<double> topDiameter(int v) const {
    auto d = diameter(v, "TopDia");
    return d ? d : diameter(v, "TopDiameter");
  }

  void drawAxes(ImportedPlant& out) {
    std::vector<double> radius(n_, -1);
    std::size_t missing = 0;
    bool first = true;
    for (std::size_t k = 0; k < out.axes.size(); ++k) {
      ImportedAxis& axis = out.axes[k];
      const Pred& base = bases_[k];
      // Radii along the axis: its own, forward-filled; leading ones from the first given, or the
      // bearer's at the insertion.
      std::vector<std::optional<double>> given;
      for (int v : axis.vertices) {
        const auto d = topDiameter(v);
        given.push_back(d ? std::optional<double>(*d / 2) : std::nullopt);
      }
      std::optional<double> firstGiven;
      for (const auto& r : given)
        if (r && !firstGiven) firstGiven = r;
      double bearerRadius = kNoDiameterMm / 2;
      if (base.vertex >= 0 && radius[static_cast<std::size_t>(base.vertex)] > 0)
        bearerRadius = radius[static_cast<std::size_t>(base.vertex)];
      double last = firstGiven.value_or(bearerRadius);
      std::vector<Ball> balls;
      const auto add = [&](const Eigen::Vector3d& c, double r) {
        if (!balls.empty() && (balls.back().center - c).norm() < 1e-6) return;
        balls.push_back({c, r});
      };
      if (base.vertex >= 0) {
        axis.base = Ball{points_[static_cast<std::size_t>(base.vertex)], firstGiven.value_or(bearerRadius)};
        axis.baseVertex = base.vertex;
      } else if (base.complex >= 0) {
        // The base's diameter: the first entity's BottomDiameter, else the complex's own (read
        // like its coordinates: at the base), else the first given along the axis.
        auto bottom = diameter(axis.vertices.front(), "BottomDiameter");
        if (!bottom) bottom = topDiameter(base.complex);
        axis.base = Ball{points_[static_cast<std::size_t>(base.complex)],
                         bottom ? *bottom / 2 : firstGiven.value_or(bearerRadius)};
      }
      if (axis.base) add(axis.base->center, axis.base->radius);
      for (std::size_t i = 0; i < axis.vertices.size(); ++i) {
        if (given[i]) {
          last = *given[i];
        } else {
          ++missing;
        }
        radius[static_cast<std::size_t>(axis.vertices[i])] = last;
        axis.balls.push_back({points_[static_cast<std::size_t>(axis.vertices[i])], last});
        add(axis.balls.back().center, last);
      }
      axis.drawnPoints = balls.size();
      for (const Ball& b : balls) {
        if (first) {
          out.low = out.high = b.center;
          first = false;
        }
        out.low = out.low.cwiseMin(b.center);
        out.high = out.high.cwiseMax(b.center);
      }
      if (balls.size() < 2) continue;
      // Zero-radius balls (a diameter of 0 in the file) would make a degenerate tube: the
      // thinnest drawable wire instead, said in the notes.
      for (Ball& b : balls) b.radius = std::max(b.radius, 0.01);
      Vein vein{"axis-" + std::to_string(k + 1), BallBSplineCurve::interpolate(balls)};
      if (!out.plant.stem && axis.order == 1) {
        double length = 0;
        for (std::size_t i = 1; i < balls.size(); ++i) length += (balls[i].center - balls[i - 1].center).norm();
        out.plant.stemHeightMm = length;
        out.plant.stemBaseDiameterMm = 2 * balls.front().radius;
        out.plant.stemTopDiameterMm = 2 * balls.back().radius;
        vein.name = "stem";
        out.plant.stem = std::move(vein);
      } else {
        out.plant.branches.push_back(std::move(vein));
      }
    }
    out.diametersMissing = missing;
  }

  const MtgArchive& a_;
  const ArchiveImportOptions& o_;
  std::size_t n_;
  int plant_ = -1;
  std::vector<bool> inPlant_, hasXyz_, below_, geometric_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::vector<int>> components_;
  std::vector<int> follower_, top_, axisOf_;
  std::vector<Pred> bases_;
};

}  // namespace

ImportedPlant importMtgPlant(const MtgArchive& archive, const ArchiveImportOptions& options) {
  if (!(options.mmPerUnit > 0) || !std::isfinite(options.mmPerUnit))
    throw InputError("the archive's length unit must be a number of millimetres above 0");
  return Importer(archive, options).run();
}

ImportedFile importMtgFile(const std::filesystem::path& path, const std::filesystem::path& drf,
                           const std::string& units, int plant) {
  // The file's kind: an MTG by its extension, a HydroShoot table by its header.
  const bool mtg = lowerExtension(path) == ".mtg";
  std::string text;
  if (!mtg) {
    text = readFile(path);
    if (!looksLikeHydroShootTable(text))
      throw InputError(path.string() +
                       ": leafdig imports AMAP / OpenAlea MTG files (.mtg) and HydroShoot's digitizing tables "
                       "(a header Souche;tronc;element;sarment;rameau;rang;X;Y;Z[;Diam]); this is neither");
    if (!drf.empty())
      throw InputError(drf.string() + ": a dressing file goes with an MTG file; a HydroShoot table has none");
  }
  // A HydroShoot table is in cm unless said otherwise; an MTG does not say its unit.
  const std::string unit = !mtg && units.empty() ? "cm" : units;
  if (unit != "mm" && unit != "cm" && unit != "m")
    throw InputError("units \"" + unit + "\": " +
                     (mtg ? "an MTG file does not say the unit of its coordinates: give mm, cm or m"
                          : "give mm, cm or m (a HydroShoot table is in cm)"));
  ArchiveImportOptions options;
  options.mmPerUnit = unit == "m" ? 1000.0 : unit == "cm" ? 10.0 : 1.0;
  options.plant = plant;
  if (!drf.empty()) options.dressing = readMtgDressing(drf);
  ImportedFile out;
  out.archive = mtg ? readMtgArchive(path) : parseHydroShootTable(text, path.string());
  out.plant = importMtgPlant(out.archive, options);
  out.unit = unit;
  return out;
}

}  // namespace leafdig::model
