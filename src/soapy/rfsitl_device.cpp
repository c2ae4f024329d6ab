#include "rfsitl_device.hpp"

#include <SoapySDR/Constants.h>
#include <SoapySDR/Errors.h>
#include <SoapySDR/Logger.hpp>

#include <cmath>
#include <mutex>
#include <set>
#include <stdexcept>
#include <utility>

namespace rfsitl::soapy {
namespace {

constexpr const char* kGainName = "DIGITAL";
constexpr const char* kFrequencyName = "RF";
/// Tunable range: the scenario's radio accepts carriers of 1 MHz to 100 GHz;
/// anything in it may be set, only the band around the carrier is heard.
constexpr double kMinFrequencyHz = 1e6, kMaxFrequencyHz = 1e11;

constexpr const char* kConnectedSensor = "connected";

/// How long getHardwareTime() waits for the emulator's first tick. A running
/// emulator ticks within milliseconds (a loaded one within a second); one
/// that waits for its other external nodes does so up to its
/// external.start_timeout_s (default 30 s), and an application that asks the
/// time before it made all their devices would otherwise hang that long.
constexpr long kFirstTickTimeoutMs = 10'000;

/// The nodes this process's devices hold: (socket, node id).
std::mutex held_mutex;
std::set<std::pair<std::string, NodeId>> held_nodes;

void check_channel(int direction, size_t channel) {
  if ((direction != SOAPY_SDR_RX && direction != SOAPY_SDR_TX) || channel != 0) {
    throw std::runtime_error("rfsitl: no channel " + std::to_string(channel) + " in direction " +
                             std::to_string(direction) + " (one RX and one TX channel, 0)");
  }
}

}  // namespace

RfsitlDevice::RfsitlDevice(const std::string& socket_path, const external::DiscoveredNode& node,
                           const NodeStreamer::Settings& settings)
    : socket_path_(socket_path), node_(node), streamer_(std::make_unique<NodeStreamer>(settings)) {
  for (auto& p : paths_) p.frequency_hz = node_.carrier_hz;
  paths_[0].gain_db = kRxGain.default_db;
  paths_[1].gain_db = kTxGain.default_db;
  apply(SOAPY_SDR_RX);
  apply(SOAPY_SDR_TX);
  std::lock_guard lock(held_mutex);
  held_nodes.emplace(socket_path_, node_.node_id);
}

RfsitlDevice::~RfsitlDevice() {
  std::lock_guard lock(held_mutex);
  held_nodes.erase({socket_path_, node_.node_id});
}

bool RfsitlDevice::held_here(const std::string& socket_path, NodeId node_id) {
  std::lock_guard lock(held_mutex);
  return held_nodes.contains({socket_path, node_id});
}

std::string RfsitlDevice::label_of(const external::DiscoveredNode& node) {
  return "rfsitl " + node.label;
}

SoapySDR::Kwargs RfsitlDevice::getHardwareInfo() const {
  return {{"node", std::to_string(node_.node_id)},
          {"label", label_of(node_)},
          {"socket", socket_path_},
          {"tick_samples", std::to_string(streamer_->tick_samples())},
          {"rx_overflows", std::to_string(streamer_->overflows())},
          {"tx_underflows", std::to_string(streamer_->underflows())},
          {"tx_late_bursts", std::to_string(streamer_->late_bursts())},
          {"link", streamer_->link_state()},
          {"rejoins", std::to_string(streamer_->rejoins())}};
}

size_t RfsitlDevice::getNumChannels(int direction) const {
  return direction == SOAPY_SDR_RX || direction == SOAPY_SDR_TX ? 1 : 0;
}

RfsitlDevice::Path& RfsitlDevice::path(int direction, size_t channel) {
  check_channel(direction, channel);
  return paths_[direction == SOAPY_SDR_RX ? 0 : 1];
}

const RfsitlDevice::Path& RfsitlDevice::path(int direction, size_t channel) const {
  check_channel(direction, channel);
  return paths_[direction == SOAPY_SDR_RX ? 0 : 1];
}

// Stream handles are the addresses of paths_[0] (RX) and paths_[1] (TX).
RfsitlDevice::Path& RfsitlDevice::path_of(SoapySDR::Stream* stream) {
  for (auto& p : paths_) {
    if (reinterpret_cast<SoapySDR::Stream*>(&p) == stream && p.stream_open) return p;
  }
  throw std::runtime_error("rfsitl: not a stream of this device (closed already?)");
}

void RfsitlDevice::apply(int direction) {
  const Path& p = path(direction, 0);
  const double fs = streamer_->sample_rate_hz();
  PathTuning t;
  t.offset_hz = p.frequency_hz - node_.carrier_hz;
  t.in_band = std::abs(t.offset_hz) < fs / 2.0;
  t.gain_db = gain_control(direction).scale_db(p.gain_db);
  if (direction == SOAPY_SDR_RX) {
    streamer_->set_rx_tuning(t);
  } else {
    streamer_->set_tx_tuning(t);
  }
}

std::vector<std::string> RfsitlDevice::getStreamFormats(int direction, size_t channel) const {
  check_channel(direction, channel);
  return format_names();
}

std::string RfsitlDevice::getNativeStreamFormat(int direction, size_t channel,
                                                double& full_scale) const {
  check_channel(direction, channel);
  full_scale = 1.0;
  return SOAPY_SDR_CF32;
}

SoapySDR::Stream* RfsitlDevice::setupStream(int direction, const std::string& format,
                                            const std::vector<size_t>& channels,
                                            const SoapySDR::Kwargs&) {
  if (channels.size() > 1 || (channels.size() == 1 && channels[0] != 0)) {
    throw std::runtime_error("rfsitl: streams have one channel, 0");
  }
  Path& p = path(direction, 0);
  if (p.stream_open) throw std::runtime_error("rfsitl: a stream of this direction is open already");
  p.format = format_of(format);
  p.stream_open = true;
  apply(direction);
  return reinterpret_cast<SoapySDR::Stream*>(&p);
}

void RfsitlDevice::closeStream(SoapySDR::Stream* stream) {
  Path& p = path_of(stream);
  if (&p == &paths_[0]) streamer_->set_rx_active(false);
  p.stream_open = false;
}

size_t RfsitlDevice::getStreamMTU(SoapySDR::Stream*) const {
  return streamer_->tick_samples();  // one message of the protocol each way per tick
}

int RfsitlDevice::activateStream(SoapySDR::Stream* stream, int, long long, size_t) {
  if (&path_of(stream) == &paths_[0]) streamer_->set_rx_active(true);
  return 0;
}

int RfsitlDevice::deactivateStream(SoapySDR::Stream* stream, int, long long) {
  if (&path_of(stream) == &paths_[0]) streamer_->set_rx_active(false);
  return 0;
}

int RfsitlDevice::readStream(SoapySDR::Stream* stream, void* const* buffs, size_t num_elems,
                             int& flags, long long& time_ns, long timeout_us) {
  Path& p = path_of(stream);
  if (&p != &paths_[0]) return SOAPY_SDR_NOT_SUPPORTED;
  std::span<cf32> out;
  if (p.format == SampleFormat::kCF32) {
    out = {static_cast<cf32*>(buffs[0]), num_elems};
  } else {
    scratch_.resize(num_elems);
    out = scratch_;
  }
  SampleTime t = 0;
  const int n = streamer_->read(out, t, timeout_us);
  flags = 0;
  if (n <= 0) return n;
  if (p.format != SampleFormat::kCF32) {
    convert_out(out.first(static_cast<size_t>(n)), p.format, buffs[0]);
  }
  flags = SOAPY_SDR_HAS_TIME;
  time_ns = streamer_->to_ns(t);
  return n;
}

int RfsitlDevice::writeStream(SoapySDR::Stream* stream, const void* const* buffs, size_t num_elems,
                              int& flags, long long time_ns, long timeout_us) {
  Path& p = path_of(stream);
  if (&p != &paths_[1]) return SOAPY_SDR_NOT_SUPPORTED;
  std::span<const cf32> in;
  if (p.format == SampleFormat::kCF32) {
    in = {static_cast<const cf32*>(buffs[0]), num_elems};
  } else {
    tx_scratch_.resize(num_elems);
    convert_in(buffs[0], p.format, tx_scratch_);
    in = tx_scratch_;
  }
  const bool timed = (flags & SOAPY_SDR_HAS_TIME) != 0;
  const bool end_burst = (flags & SOAPY_SDR_END_BURST) != 0;
  const SampleTime at = timed ? streamer_->to_samples(time_ns) : 0;
  flags = 0;
  return streamer_->write(in, timed ? &at : nullptr, end_burst, timeout_us);
}

int RfsitlDevice::readStreamStatus(SoapySDR::Stream* stream, size_t& chan_mask, int& flags,
                                   long long& time_ns, long timeout_us) {
  if (&path_of(stream) != &paths_[1]) return SOAPY_SDR_NOT_SUPPORTED;
  TxEvent e;
  const int rc = streamer_->read_event(e, timeout_us);
  if (rc != 0) return rc;
  chan_mask = 1;
  flags = SOAPY_SDR_HAS_TIME;
  time_ns = streamer_->to_ns(e.time);
  return e.code;
}

std::vector<std::string> RfsitlDevice::listAntennas(int direction, size_t channel) const {
  check_channel(direction, channel);
  return {direction == SOAPY_SDR_RX ? "RX" : "TX"};
}

std::string RfsitlDevice::getAntenna(int direction, size_t channel) const {
  return listAntennas(direction, channel).front();
}

std::vector<std::string> RfsitlDevice::listGains(int direction, size_t channel) const {
  check_channel(direction, channel);
  return {kGainName};
}

const GainControl& RfsitlDevice::gain_control(int direction) {
  return direction == SOAPY_SDR_RX ? kRxGain : kTxGain;
}

void RfsitlDevice::setGain(int direction, size_t channel, double value) {
  Path& p = path(direction, channel);
  const GainControl& g = gain_control(direction);
  const double set = g.clamp(value);
  if (std::isnan(set)) throw std::runtime_error("rfsitl: gain NaN is not a number of dB");
  if (set != value) {
    SoapySDR::logf(SOAPY_SDR_WARNING,
                   "rfsitl node %u: %s gain %g dB is outside %g..%g dB: set to %g",
                   unsigned{node_.node_id}, direction == SOAPY_SDR_RX ? "RX" : "TX", value,
                   g.min_db, g.max_db, set);
  }
  p.gain_db = set;
  apply(direction);
}

void RfsitlDevice::setGain(int direction, size_t channel, const std::string& name, double value) {
  if (name != kGainName) throw std::runtime_error("rfsitl: no gain element '" + name + "'");
  setGain(direction, channel, value);
}

double RfsitlDevice::getGain(int direction, size_t channel) const {
  return path(direction, channel).gain_db;
}

double RfsitlDevice::getGain(int direction, size_t channel, const std::string&) const {
  return getGain(direction, channel);
}

SoapySDR::Range RfsitlDevice::getGainRange(int direction, size_t channel) const {
  check_channel(direction, channel);
  const GainControl& g = gain_control(direction);
  return {g.min_db, g.max_db, 0.0};
}

SoapySDR::Range RfsitlDevice::getGainRange(int direction, size_t channel,
                                           const std::string&) const {
  return getGainRange(direction, channel);
}

void RfsitlDevice::setFrequency(int direction, size_t channel, double frequency,
                                const SoapySDR::Kwargs&) {
  if (!(frequency >= kMinFrequencyHz && frequency <= kMaxFrequencyHz)) {
    throw std::runtime_error("rfsitl: frequency " + std::to_string(frequency) +
                             " Hz outside 1 MHz .. 100 GHz");
  }
  path(direction, channel).frequency_hz = frequency;
  apply(direction);
}

void RfsitlDevice::setFrequency(int direction, size_t channel, const std::string& name,
                                double frequency, const SoapySDR::Kwargs& args) {
  if (name != kFrequencyName)
    throw std::runtime_error("rfsitl: no frequency element '" + name + "'");
  setFrequency(direction, channel, frequency, args);
}

double RfsitlDevice::getFrequency(int direction, size_t channel) const {
  return path(direction, channel).frequency_hz;
}

double RfsitlDevice::getFrequency(int direction, size_t channel, const std::string&) const {
  return getFrequency(direction, channel);
}

std::vector<std::string> RfsitlDevice::listFrequencies(int direction, size_t channel) const {
  check_channel(direction, channel);
  return {kFrequencyName};
}

SoapySDR::RangeList RfsitlDevice::getFrequencyRange(int direction, size_t channel) const {
  check_channel(direction, channel);
  return {SoapySDR::Range(kMinFrequencyHz, kMaxFrequencyHz)};
}

SoapySDR::RangeList RfsitlDevice::getFrequencyRange(int direction, size_t channel,
                                                    const std::string&) const {
  return getFrequencyRange(direction, channel);
}

void RfsitlDevice::setSampleRate(int direction, size_t channel, double rate) {
  check_channel(direction, channel);
  const double fs = streamer_->sample_rate_hz();
  if (std::abs(rate - fs) > 1e-9 * fs) {
    throw std::runtime_error("rfsitl: the emulator runs at " + std::to_string(fs) +
                             " Sa/s; setSampleRate(" + std::to_string(rate) +
                             ") is not supported (the module does not resample)");
  }
}

double RfsitlDevice::getSampleRate(int direction, size_t channel) const {
  check_channel(direction, channel);
  return streamer_->sample_rate_hz();
}

std::vector<double> RfsitlDevice::listSampleRates(int direction, size_t channel) const {
  return {getSampleRate(direction, channel)};
}

SoapySDR::RangeList RfsitlDevice::getSampleRateRange(int direction, size_t channel) const {
  const double fs = getSampleRate(direction, channel);
  return {SoapySDR::Range(fs, fs)};
}

double RfsitlDevice::getBandwidth(int direction, size_t channel) const {
  return getSampleRate(direction, channel);
}

SoapySDR::RangeList RfsitlDevice::getBandwidthRange(int direction, size_t channel) const {
  return getSampleRateRange(direction, channel);
}

std::vector<std::string> RfsitlDevice::listSensors() const {
  return {kConnectedSensor};
}

SoapySDR::ArgInfo RfsitlDevice::getSensorInfo(const std::string& key) const {
  if (key != kConnectedSensor) throw std::runtime_error("rfsitl: no sensor '" + key + "'");
  SoapySDR::ArgInfo info;
  info.key = kConnectedSensor;
  info.name = "Connected to the emulator";
  info.type = SoapySDR::ArgInfo::BOOL;
  info.value = "true";
  info.description = "false once the emulator closed the connection (stopped or dropped us)";
  return info;
}

std::string RfsitlDevice::readSensor(const std::string& key) const {
  if (key != kConnectedSensor) throw std::runtime_error("rfsitl: no sensor '" + key + "'");
  return streamer_->connected() ? "true" : "false";
}

long long RfsitlDevice::getHardwareTime(const std::string&) const {
  SampleTime t = 0;
  if (!streamer_->now_after_first_tick(t, kFirstTickTimeoutMs * 1000)) {
    const std::string why =
        streamer_->connected()
            ? "no tick came within " + std::to_string(kFirstTickTimeoutMs / 1000) +
                  " s (an emulator waits for all its external nodes before its first tick, "
                  "up to external.start_timeout_s: make every node's device first)"
            : "the emulator closed the connection before its first tick";
    throw std::runtime_error("rfsitl node " + std::to_string(node_.node_id) + " of " +
                             socket_path_ + ": no hardware time yet: " + why);
  }
  return streamer_->to_ns(t);
}

void RfsitlDevice::setHardwareTime(long long, const std::string&) {
  throw std::runtime_error(
      "rfsitl: hardware time is the emulator's virtual time; it cannot be set");
}

}  // namespace rfsitl::soapy
