#include "capture/sounds.hpp"

#include <QApplication>
#include <QAudioDevice>
#include <QFile>
#include <QMediaDevices>
#include <QtEndian>
#include <algorithm>
#include <cmath>

namespace leafdig::station {
namespace {

void put16(QByteArray& b, quint16 v) {
  const quint16 le = qToLittleEndian(v);
  b.append(reinterpret_cast<const char*>(&le), 2);
}
void put32(QByteArray& b, quint32 v) {
  const quint32 le = qToLittleEndian(v);
  b.append(reinterpret_cast<const char*>(&le), 4);
}

}  // namespace

QByteArray synthesizeWav(const std::vector<std::pair<double, double>>& tones, int sampleRate) {
  QByteArray pcm;
  for (const auto& [hz, seconds] : tones) {
    const int n = static_cast<int>(seconds * sampleRate);
    const int fade = std::max(1, sampleRate / 200);  // 5 ms: no clicks
    for (int i = 0; i < n; ++i) {
      const double envelope = std::min({1.0, static_cast<double>(i) / fade, static_cast<double>(n - i) / fade});
      const double v = hz > 0 ? 0.45 * envelope * std::sin(2.0 * M_PI * hz * i / sampleRate) : 0.0;
      put16(pcm, static_cast<quint16>(static_cast<qint16>(std::lround(v * 32767))));
    }
  }
  QByteArray wav("RIFF");
  put32(wav, static_cast<quint32>(36 + pcm.size()));
  wav.append("WAVEfmt ");
  put32(wav, 16);
  put16(wav, 1);  // PCM
  put16(wav, 1);  // mono
  put32(wav, static_cast<quint32>(sampleRate));
  put32(wav, static_cast<quint32>(sampleRate * 2));
  put16(wav, 2);
  put16(wav, 16);
  wav.append("data");
  put32(wav, static_cast<quint32>(pcm.size()));
  return wav + pcm;
}

Sounds::Sounds(QObject* parent, bool audio) : QObject(parent) {
  if (!audio) return;
  const std::array<std::vector<std::pair<double, double>>, 4> tones{{
      {{1318.5, 0.07}},                                              // accept: one short high tick
      {{220.0, 0.12}, {0, 0.05}, {220.0, 0.12}},                     // reject: two low buzzes
      {{880.0, 0.08}, {1108.7, 0.08}, {1318.5, 0.12}},               // step done: rising triad
      {{660.0, 0.15}, {440.0, 0.15}, {660.0, 0.15}, {440.0, 0.15}},  // device error: two-tone alarm
  }};
  for (std::size_t i = 0; i < tones.size(); ++i) {
    const QString path = file(static_cast<Cue>(i));
    QFile f(path);
    if (f.open(QIODevice::WriteOnly)) f.write(synthesizeWav(tones[i]));
    f.close();
    effects_[i] = std::make_unique<QSoundEffect>(this);
    effects_[i]->setSource(QUrl::fromLocalFile(path));  // loads now: preloaded
    effects_[i]->setVolume(0.8f);
  }
}

QString Sounds::file(Cue cue) const {
  static const char* names[] = {"accept.wav", "reject.wav", "step.wav", "error.wav"};
  return dir_.filePath(names[static_cast<std::size_t>(cue)]);
}

bool Sounds::loading() const {
  return std::any_of(effects_.begin(), effects_.end(),
                     [](const auto& e) { return e && e->status() == QSoundEffect::Loading; });
}

void Sounds::setVolume(double v) {
  for (auto& e : effects_)
    if (e) e->setVolume(static_cast<float>(std::clamp(v, 0.0, 1.0)));
}

void Sounds::play(Cue cue) {
  const auto i = static_cast<std::size_t>(cue);
  ++requested_[i];
  if (muted_) return;
  if (!effects_[i] || effects_[i]->status() == QSoundEffect::Error || QMediaDevices::audioOutputs().isEmpty()) {
    // No sound output (or it failed): the important cues still make a noise.
    if (cue == Cue::Reject || cue == Cue::DeviceError) QApplication::beep();
    return;
  }
  effects_[i]->play();
  ++played_[i];
}

}  // namespace leafdig::station
