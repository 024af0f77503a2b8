// PlantEngine's state changes (plant_engine.hpp): a decision applied (live and on replay), a
// curator's correction put where the old item stood, and the captured plant as plant markers.
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "leafdig/acquisition/protocol/marker_set.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/model/plant/plant_frame.hpp"

namespace leafdig::acquisition {

namespace {

namespace m = leafdig::model;

rules::Point at(const PlantItem& i) {
  return rules::toPoint(i.positionMm);
}

}  // namespace

void PlantEngine::eraseItem(std::size_t index) {
  items_.erase(items_.begin() + static_cast<std::ptrdiff_t>(index));
  foundValid_ = false;
  // The plant's item actions are in the order of items_: the index-th of them goes with it.
  std::size_t k = 0;
  for (auto it = actions_.begin(); it != actions_.end(); ++it)
    if (it->kind == Action::Kind::Item && k++ == index) {
      actions_.erase(it);
      break;
    }
}

void PlantEngine::mirror(int node, const Decision& d) {
  switch (d.kind) {
    case Decision::Kind::Accepted:
    case Decision::Kind::RowsEnded:
    case Decision::Kind::RetakeCancelled:
      actions_.push_back({Action::Kind::Leaf, node, {}, false, std::nullopt});
      break;
    case Decision::Kind::Undone:
    case Decision::Kind::RowsReopened:
    case Decision::Kind::RetakeStarted:
      for (auto it = actions_.rbegin(); it != actions_.rend(); ++it)
        if (it->kind == Action::Kind::Leaf && it->node == node) {
          actions_.erase(std::next(it).base());
          break;
        }
      break;
    default: break;
  }
}

void PlantEngine::apply(const PlantDecision& d) {
  switch (d.kind) {
    case PlantDecision::Kind::Accepted:
      items_.push_back(d.item);
      foundValid_ = false;
      actions_.push_back({Action::Kind::Item, 0, {}, false, std::nullopt});
      if (retake_ && retake_->what == d.item.what && retake_->index == d.item.index && retake_->part == d.item.part)
        retake_.reset();
      break;
    case PlantDecision::Kind::RetakeStarted:
      for (std::size_t i = 0; i < items_.size(); ++i)
        if (items_[i].what == d.item.what && items_[i].index == d.item.index && items_[i].part == d.item.part) {
          eraseItem(i);
          retake_ = PlantStep{d.item.what, d.item.index, d.item.part, {}};
          retakeOld_ = d.item;
          break;
        }
      break;
    case PlantDecision::Kind::RetakeCancelled:
      if (retake_) {
        items_.push_back(d.item);
        foundValid_ = false;
        actions_.push_back({Action::Kind::Item, 0, {}, false, std::nullopt});
        retake_.reset();
      }
      break;
    case PlantDecision::Kind::Undone:
      if (!actions_.empty() && actions_.back().kind == Action::Kind::Item && !items_.empty()) {
        items_.pop_back();
        foundValid_ = false;
        actions_.pop_back();
      }
      break;
    case PlantDecision::Kind::LandmarksEnded:
      landmarksEnded_ = true;
      actions_.push_back({Action::Kind::LandmarksEnded, 0, {}, false, std::nullopt});
      break;
    case PlantDecision::Kind::LandmarksReopened:
      landmarksEnded_ = false;
      if (!actions_.empty() && actions_.back().kind == Action::Kind::LandmarksEnded) actions_.pop_back();
      break;
    case PlantDecision::Kind::PlantEnded:
      plantEnded_ = true;
      actions_.push_back({Action::Kind::PlantEnded, 0, {}, false, std::nullopt});
      break;
    case PlantDecision::Kind::PlantReopened:
      plantEnded_ = false;
      if (!actions_.empty() && actions_.back().kind == Action::Kind::PlantEnded) actions_.pop_back();
      break;
    case PlantDecision::Kind::LeafChosen: {
      const bool had = choices_.count(d.node) > 0;
      actions_.push_back({Action::Kind::Choice, d.node, had ? choices_[d.node] : LeafChoice{}, had, std::nullopt});
      choices_[d.node] = d.choice;
      break;
    }
    case PlantDecision::Kind::ChoiceUndone:
      if (!actions_.empty() && actions_.back().kind == Action::Kind::Choice) {
        const Action a = actions_.back();
        actions_.pop_back();
        if (a.hadChoice)
          choices_[a.node] = a.previous;
        else
          choices_.erase(a.node);
      }
      break;
    case PlantDecision::Kind::Leaf:
      leafEngine(d.node).apply(d.leaf);
      mirror(d.node, d.leaf);
      if (d.leaf.kind == Decision::Kind::Accepted && isStylusItem(d.leaf.item.what))
        leafPositions_[d.node].insert(static_cast<int>(toFirst_.size()) - 1);
      break;
    case PlantDecision::Kind::RelocationStarted:
      relocating_ = d.node;
      actions_.push_back({Action::Kind::RelocationStart, d.node, {}, false, std::nullopt});
      break;
    case PlantDecision::Kind::RelocationFitted:
      if (relocating_ == d.node) {
        toFirst_.push_back(fitOf(d.node).newToOld);  // recomputed: replay gives the same
        relocating_ = 0;
        actions_.push_back({Action::Kind::RelocationFit, d.node, {}, false, std::nullopt});
      }
      break;
    case PlantDecision::Kind::RelocationReopened:
      if (!actions_.empty() && actions_.back().kind == Action::Kind::RelocationFit && toFirst_.size() > 1) {
        relocating_ = actions_.back().node;
        actions_.pop_back();
        toFirst_.pop_back();
      }
      break;
    case PlantDecision::Kind::RelocationCancelled:
      if (!actions_.empty() && actions_.back().kind == Action::Kind::RelocationStart) {
        actions_.pop_back();
        relocating_ = 0;
      }
      break;
    case PlantDecision::Kind::NodePlaced: {
      Action a{Action::Kind::Place, d.node, {}, false, std::nullopt};
      if (const auto it = places_.find(d.node); it != places_.end()) a.previousPlace = it->second;
      actions_.push_back(a);
      places_[d.node] = d.place;
      relink();
      break;
    }
    case PlantDecision::Kind::PlacementUndone:
      if (!actions_.empty() && actions_.back().kind == Action::Kind::Place) {
        const Action a = actions_.back();
        actions_.pop_back();
        if (a.previousPlace)
          places_[a.node] = *a.previousPlace;
        else
          places_.erase(a.node);
        relink();
      }
      break;
    default: break;
  }
}

bool PlantEngine::correct(const PlantItem& fixed) {
  for (PlantItem& i : items_)
    if (i.what == fixed.what && i.index == fixed.index && i.part == fixed.part) {
      i = fixed;
      return true;
    }
  return false;
}

bool PlantEngine::correctLeaf(int node, const Item& fixed) {
  const auto it = leaves_.find(node);
  if (it == leaves_.end()) return false;
  Engine& e = it->second;
  for (const Item& old : e.items())
    if (old.what == fixed.what && old.row == fixed.row && old.col == fixed.col) {
      Decision out;
      out.kind = Decision::Kind::RetakeStarted;
      out.item = old;
      e.apply(out);  // `old` is gone from here on
      Decision in;
      in.kind = Decision::Kind::Accepted;
      in.item = fixed;
      e.apply(in);
      return true;
    }
  return false;
}

m::PlantMarkers PlantEngine::captured(const std::string& plant) const {
  m::PlantMarkers out;
  out.plant = plant;
  out.landmarksMm = landmarkPoints();  // by number: a retaken landmark keeps its place
  if (const PlantItem* c = find(PlantWhat::Collar, 0, 0)) out.collarMm = at(*c);
  if (const PlantItem* c = find(PlantWhat::CollarDiameter, 0, 0)) out.collarDiameterMm = c->valueMm;
  for (int node = 1; node <= nodes(); ++node) {
    m::PlantNode n;
    if (const auto where = places_.find(node); where != places_.end()) {
      if (where->second.relation == '+')
        n.branchesFrom = where->second.parent;
      else if (where->second.parent != node - 1)
        n.after = where->second.parent;
    }
    n.pointMm = at(*find(PlantWhat::Point, node, 1));
    if (const PlantItem* r = find(PlantWhat::Reading, node, 1)) n.diameterMm = r->valueMm;
    const LeafChoice choice = choiceFor(node);
    n.state = choice.state;
    const m::ProtocolEntity* leafIs = leafEntityOf(node);
    if (leafIs && choice.kind == m::LeafKind::Full) {
      if (const Engine* e = leaf(node); e && e->complete()) {
        m::MarkerSet set = toMarkerSet(e->items(), settings_);
        set.leaf.type = choice.type;
        n.leaf = std::move(set);
      }
    } else if (leafIs && choice.kind == m::LeafKind::Quick) {
      const PlantItem* b = find(PlantWhat::QuickPoint, node, 1);
      const PlantItem* t = find(PlantWhat::QuickPoint, node, 2);
      const PlantItem* s = find(PlantWhat::QuickPoint, node, 3);
      if (b && t && s) n.leaf = m::QuickLeaf{at(*b), at(*t), at(*s), choice.type};
    }
    out.nodes.push_back(std::move(n));
  }
  return out;
}

}  // namespace leafdig::acquisition
