#include "leafdig/acquisition/live/leaf_loop.hpp"

#include <sstream>
#include <stdexcept>

namespace leafdig::acquisition {

Step parseLeafItemWords(std::istream& in, const std::string& command) {
  std::string what;
  in >> what;
  if (what.empty())
    throw std::invalid_argument(command + " what? e.g. '" + command + " marker 3 5', '" + command + " tip', '" +
                                command + " midrib_thickness 2'");
  Step st;
  st.what = whatFromString(what);
  if (st.what == What::Marker || st.what == What::PointThickness) {
    if (!(in >> st.row >> st.col))
      throw std::invalid_argument(command + " " + what + " needs a row and a point: e.g. '" + command + " " + what +
                                  " 3 5'");
  } else if (st.what == What::MidribThickness || st.what == What::VeinOriginThickness) {
    if (!(in >> st.row))
      throw std::invalid_argument(command + " " + what + " needs a row: e.g. '" + command + " " + what + " 2'");
    st.col = 4;
  } else if (st.what == What::Board) {
    if (!(in >> st.col)) throw std::invalid_argument(command + " board needs the point (1, 2 or 3)");
  }
  return st;
}

void readMoveWords(std::istream& in) {
  std::string what;
  if (in >> what && what != "transmitter")
    throw std::invalid_argument("'move' takes no words but 'transmitter' (got '" + what + "')");
}

Command parseCommand(const std::string& line) {
  std::istringstream in(line);
  std::string word;
  in >> word;
  Command c;
  if (word == "undo" || word == "u")
    c.kind = Command::Kind::Undo;
  else if (word == "end" || word == "e")
    c.kind = Command::Kind::EndRows;
  else if (word == "pause" || word == "p")
    c.kind = Command::Kind::Pause;
  else if (word == "resume")
    c.kind = Command::Kind::Resume;
  else if (word == "quit" || word == "q")
    c.kind = Command::Kind::Quit;
  else if (word == "abandon")
    c.kind = Command::Kind::Abandon;
  else if (word == "move") {
    c.kind = Command::Kind::MoveTransmitter;
    readMoveWords(in);
  } else if (word == "retake" || word == "r") {
    c.kind = Command::Kind::Retake;
    const Step st = parseLeafItemWords(in, "retake");
    c.what = st.what;
    c.row = st.row;
    c.col = st.col;
  } else {
    throw std::invalid_argument(
        "unknown command '" + word +
        "': use undo, end, retake WHAT [ROW [POINT]], move (the transmitter), pause, resume, abandon [why], "
        "quit");
  }
  std::getline(in >> std::ws, c.text);
  return c;
}

LiveLeaf::LiveLeaf(CaptureSession& session, LoopListener listener, double timeScale, PreviewDetail preview,
                   PreviewBuilder builder)
    : session_(session),
      listener_(std::move(listener)),
      timeScale_(timeScale),
      preview_(preview),
      builder_(builder ? std::move(builder)
                       : PreviewBuilder([](const std::vector<Item>& items, const Settings& settings) {
                           return buildPreview(items, settings, {}, true);
                         })) {}

LiveLeaf::~LiveLeaf() {
  stopWorker();
}

void LiveLeaf::deliver(const std::vector<Feedback>& feedback) {
  for (const Feedback& f : feedback)
    if (listener_.onFeedback) listener_.onFeedback(f);
  if (!feedback.empty()) publish();
}

void LiveLeaf::publish() {
  if (preview_ != PreviewDetail::Meshes) {
    if (listener_.onSnapshot) listener_.onSnapshot(session_.snapshot(preview_ == PreviewDetail::Model, false));
    return;
  }
  Snapshot s = session_.snapshot(false);
  PreviewJob job{s.version, s.items, session_.engine().settings()};
  {
    std::lock_guard lock(publishMutex_);
    s.preview = latest_.preview;  // the newest built so far
    s.previewVersion = latest_.previewVersion;
    latest_ = s;
    if (listener_.onSnapshot) listener_.onSnapshot(s);
  }
  {
    std::lock_guard lock(jobMutex_);
    job_ = std::move(job);
  }
  jobCv_.notify_one();
}

void LiveLeaf::buildPreviews() {
  for (;;) {
    PreviewJob job;
    {
      std::unique_lock lock(jobMutex_);
      jobCv_.wait(lock, [&] { return job_.has_value() || workerStop_; });
      if (!job_) return;  // stopping, and the newest request is built
      job = std::move(*job_);
      job_.reset();
    }
    std::shared_ptr<const Preview> built;
    try {
      built = std::make_shared<const Preview>(builder_(job.items, job.settings));
    } catch (const std::exception& e) {
      // buildPreview leaves out what it cannot build; this is memory or worse. Say so on the
      // screen and keep capturing: the preview is never the record.
      auto failed = std::make_shared<Preview>();
      failed->notes.push_back(std::string("the preview could not be built: ") + e.what());
      built = std::move(failed);
    }
    std::lock_guard lock(publishMutex_);
    if (job.version < latest_.previewVersion) continue;
    latest_.preview = built;
    latest_.previewVersion = job.version;
    if (listener_.onSnapshot) listener_.onSnapshot(latest_);
  }
}

void LiveLeaf::stopWorker() {
  if (!worker_.joinable()) return;
  {
    std::lock_guard lock(jobMutex_);
    workerStop_ = true;
  }
  jobCv_.notify_one();
  worker_.join();
}

bool LiveLeaf::command(const Command& c, std::int64_t now) {
  switch (c.kind) {
    case Command::Kind::Undo: deliver(session_.undo(now)); break;
    case Command::Kind::EndRows: deliver(session_.endRows(now)); break;
    case Command::Kind::Retake: deliver(session_.retake(c.what, c.row, c.col, now)); break;
    case Command::Kind::MoveTransmitter: deliver(session_.moveTransmitter(now)); break;
    case Command::Kind::Pause: deliver(session_.pause(c.text.empty() ? "operator pause" : c.text, now)); break;
    case Command::Kind::Resume: deliver(session_.resume(now)); break;
    case Command::Kind::Abandon:
      deliver(session_.abandon(c.text.empty() ? "abandoned by the operator" : c.text, now));
      break;
    case Command::Kind::Quit: return false;
  }
  return true;
}

void LiveLeaf::begin(Listen /*unused*/) {
  if (preview_ == PreviewDetail::Meshes && !worker_.joinable()) {
    workerStop_ = false;
    worker_ = std::thread([this] { buildPreviews(); });
  }
  publish();
}

Snapshot LiveLeaf::finish() {
  if (preview_ != PreviewDetail::Meshes) return session_.snapshot(preview_ == PreviewDetail::Model, false);
  stopWorker();  // builds the newest request first: latest_ has the preview of its version
  std::lock_guard lock(publishMutex_);
  return latest_;
}

template class CaptureLoop<LiveLeaf>;

}  // namespace leafdig::acquisition
