// Audible cues (aesthetics §3): distinct short sounds for accept, reject, step done and a
// device error, synthesised once at start-up into WAV files and preloaded as QSoundEffects,
// so a cue starts without decoding. With no audio output the station beeps (reject, error)
// and says so in the settings; muting silences all of them. Without audio (`--no-audio`:
// a machine with no sound, or where Qt Multimedia is not wanted) nothing is synthesised or
// loaded and the two important cues are the system beep.
#pragma once

#include <QObject>
#include <QSoundEffect>
#include <QTemporaryDir>
#include <array>
#include <memory>

namespace leafdig::station {

enum class Cue { Accept, Reject, StepDone, DeviceError };

class Sounds : public QObject {
  Q_OBJECT

 public:
  explicit Sounds(QObject* parent = nullptr, bool audio = true);
  void play(Cue cue);
  void setMuted(bool muted) { muted_ = muted; }
  [[nodiscard]] bool muted() const { return muted_; }
  void setVolume(double v);
  // Every cue requested (muted or not) and those actually sent to a sound output: the
  // widget tests check the cue logic with them.
  [[nodiscard]] int requested(Cue cue) const { return requested_[static_cast<std::size_t>(cue)]; }
  [[nodiscard]] int played(Cue cue) const { return played_[static_cast<std::size_t>(cue)]; }
  // Whether a cue's sound has finished loading (Ready, or Error when there is no output);
  // Qt loads the samples on a thread of its own. Tests wait for it before they end: Qt 6.4
  // leaks a sample whose effect is destroyed mid-load.
  [[nodiscard]] QSoundEffect::Status status(Cue cue) const {
    const auto& e = effects_[static_cast<std::size_t>(cue)];
    return e ? e->status() : QSoundEffect::Null;
  }
  [[nodiscard]] bool loading() const;
  // The WAV file behind a cue (valid while this object lives).
  [[nodiscard]] QString file(Cue cue) const;

 private:
  QTemporaryDir dir_;
  std::array<std::unique_ptr<QSoundEffect>, 4> effects_;
  std::array<int, 4> requested_{}, played_{};
  bool muted_ = false;
};

// A mono 16-bit PCM WAV of tones (Hz, seconds; 0 Hz is silence), with short fades.
[[nodiscard]] QByteArray synthesizeWav(const std::vector<std::pair<double, double>>& tones, int sampleRate = 22050);

}  // namespace leafdig::station
