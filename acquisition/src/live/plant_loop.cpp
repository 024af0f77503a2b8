#include "leafdig/acquisition/live/plant_loop.hpp"

#include <sstream>
#include <stdexcept>
#include <utility>

#include "leafdig/acquisition/live/leaf_loop.hpp"

namespace leafdig::acquisition {

PlantCommand parsePlantCommand(const std::string& line) {
  std::istringstream in(line);
  std::string word;
  in >> word;
  PlantCommand c;
  if (word == "undo" || word == "u") {
    c.kind = PlantCommand::Kind::Undo;
  } else if (word == "end" || word == "e") {
    c.kind = PlantCommand::Kind::End;
  } else if (word == "quit" || word == "q") {
    c.kind = PlantCommand::Kind::Quit;
  } else if (word == "pause" || word == "p") {
    c.kind = PlantCommand::Kind::Pause;
    std::getline(in >> std::ws, c.text);
    if (c.text.size() > 200) throw std::invalid_argument("a pause's reason is a few words (at most 200 characters)");
  } else if (word == "resume" || word == "r") {
    c.kind = PlantCommand::Kind::Resume;
  } else if (word == "move") {
    c.kind = PlantCommand::Kind::MoveTransmitter;
    readMoveWords(in);
  } else if (word == "branch" || word == "b") {
    c.kind = PlantCommand::Kind::Branch;
    std::string from;
    if (in >> from) {
      if (from.empty() || from.size() > 4 || from.find_first_not_of("0123456789") != std::string::npos ||
          std::stoi(from) < 1)
        throw std::invalid_argument("'branch' takes the number of the main-stem node it starts from: branch 4 (got '" +
                                    from + "')");
      c.node = std::stoi(from);
    }
  } else if (word == "retake") {
    c.kind = PlantCommand::Kind::Retake;
    std::string what;
    if (!(in >> what))
      throw std::invalid_argument(
          "retake what? e.g. 'retake landmark 2', 'retake collar', 'retake point 4', 'retake reading 4', "
          "'retake quick_point 5 2', 'retake node 3 marker 2 5'");
    if (what == "node") {
      if (!(in >> c.node) || c.node < 1)
        throw std::invalid_argument(
            "'retake node' needs the node's number and the leaf's item: retake node 3 marker 2 5");
      c.leaf = parseLeafItemWords(in, "retake node " + std::to_string(c.node));
    } else {
      try {
        c.what = plantWhatFromString(what);
      } catch (const std::invalid_argument&) {
        throw std::invalid_argument("retake " + what +
                                    "? a plant's item is landmark N, collar, collar_diameter, point N, reading N or "
                                    "quick_point N PART; a full leaf's is 'node N' and the leaf's item");
      }
      const auto number = [&](const char* example) {
        int v = 0;
        if (!(in >> v) || v < 1) throw std::invalid_argument("'retake " + what + "' needs a number: " + example);
        return v;
      };
      switch (c.what) {
        case PlantWhat::Landmark: c.index = number("retake landmark 2"); break;
        case PlantWhat::Point:
        case PlantWhat::Reading:
          c.index = number("retake point 4 (node 4's point; a second number for another of its points)");
          c.part = 1;
          if (in >> std::ws && !in.eof()) c.part = number("retake point 4 2");
          break;
        case PlantWhat::QuickPoint:
          c.index = number("retake quick_point 5 2 (node 5's quick leaf, its point 2: the tip)");
          c.part = number("retake quick_point 5 2 (the point: 1 base, 2 tip, 3 the widest of one margin)");
          break;
        case PlantWhat::Collar:
        case PlantWhat::CollarDiameter: break;
        case PlantWhat::Leaf:
        case PlantWhat::Done:
          throw std::invalid_argument("retake " + what + "? a full leaf's item is 'retake node N' and the item");
        case PlantWhat::LandmarkAgain:
          throw std::invalid_argument("a landmark taken again after moving the transmitter is undone, not retaken");
      }
    }
  } else if (word == "leaf") {
    c.kind = PlantCommand::Kind::Choose;
    std::string kind, state, type, extra;
    if (!(in >> c.node) || c.node < 1)
      throw std::invalid_argument("'leaf' needs the node's number (1 at the base): leaf 3 quick lower");
    if (!(in >> kind)) throw std::invalid_argument("'leaf " + std::to_string(c.node) + "' needs full, quick or none");
    try {
      c.choice.kind = model::leafKindFromString(kind);
      // A state is optional; a word that is not one is the leaf's type.
      if (in >> state) {
        try {
          c.choice.state = model::leafStateFromString(state);
          in >> type;
        } catch (const std::exception&) {
          type = state;
        }
      }
    } catch (const std::exception& e) {
      throw std::invalid_argument(std::string(e.what()) + " (leaf N full|quick|none [state] [type])");
    }
    if (in >> extra) throw std::invalid_argument("'" + extra + "' is one word too many: leaf N KIND [STATE] [TYPE]");
    if (type.size() > kMaxLeafTypeChars) throw std::invalid_argument("a leaf's type is at most 64 characters");
    c.choice.type = type;
  } else {
    throw std::invalid_argument(
        "unknown command '" + line +
        "': use undo, end, leaf N full|quick|none [state] [type], retake WHAT [N [PART]], branch [N], "
        "move (the transmitter), pause [reason], resume, or quit");
  }
  if (c.kind != PlantCommand::Kind::Choose && c.kind != PlantCommand::Kind::Pause) {
    std::string extra;
    if (in >> extra) throw std::invalid_argument("'" + word + "' takes no words after it (got '" + extra + "')");
  }
  return c;
}

void LivePlant::begin(Listen listen) {
  listen_ = std::move(listen);
  stats_ = {};
  if (listen_.onChange) listen_.onChange(session_);
}

bool LivePlant::command(const PlantCommand& c, std::int64_t now) {
  switch (c.kind) {
    case PlantCommand::Kind::Undo: tell(session_.undo(now)); break;
    case PlantCommand::Kind::End: tell(session_.end(now)); break;
    case PlantCommand::Kind::Choose: tell(session_.chooseLeaf(c.node, c.choice, now)); break;
    case PlantCommand::Kind::Branch: tell(session_.branch(c.node, now)); break;
    case PlantCommand::Kind::MoveTransmitter: tell(session_.moveTransmitter(now)); break;
    case PlantCommand::Kind::Retake:
      tell(c.node > 0 ? session_.retakeLeaf(c.node, c.leaf.what, c.leaf.row, c.leaf.col, now)
                      : session_.retake(c.what, c.index, c.part, now));
      break;
    case PlantCommand::Kind::Pause: tell(session_.pause(c.text.empty() ? "operator pause" : c.text, now)); break;
    case PlantCommand::Kind::Resume: tell(session_.resume(now)); break;
    case PlantCommand::Kind::Quit: return false;
  }
  return true;
}

void LivePlant::device(const std::string& device, const std::string& state, const std::string& message,
                       std::int64_t now) {
  const PlantFeedback f = session_.deviceStatus(device, state, message, now);
  if (f.storeRefused) tell(f);  // else said by the devices' own callback; nothing for the technician
}

void LivePlant::tell(const PlantFeedback& f) {
  // Anything to tell: a decision, a refused write, a control (pause, resume, a move).
  if (f.decision.kind == PlantDecision::Kind::Ignored && !f.storeRefused && f.control == PlantFeedback::Control::None)
    return;
  if (f.decision.kind == PlantDecision::Kind::Rejected)
    ++stats_.rejected;
  else if (f.seq > 0 && f.control == PlantFeedback::Control::None)
    ++stats_.accepted;
  if (listen_.onFeedback) listen_.onFeedback(f, session_);
  if (listen_.onChange) listen_.onChange(session_);
}

template class CaptureLoop<LivePlant>;

}  // namespace leafdig::acquisition
