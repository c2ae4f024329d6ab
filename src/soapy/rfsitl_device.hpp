#pragma once
/// `driver=rfsitl`: one node of a running emulator as a SoapySDR device with
/// one RX and one TX channel (channel 0). The sample rate is the emulator's
/// and cannot change; the frequency is the scenario's radio carrier, and
/// tuning elsewhere shifts the samples (inside +-fs/2) or silences the
/// direction (outside); gains scale the samples onto one digital full scale
/// (signal_path.hpp: kRxGain, kTxGain); hardware time is the virtual time in
/// nanoseconds. Streaming goes through NodeStreamer, whose thread
/// answers the emulator, so a slow application never stalls it.
#include <SoapySDR/Device.hpp>

#include <array>
#include <memory>
#include <string>

#include "node_streamer.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "sample_formats.hpp"

namespace rfsitl::soapy {

class RfsitlDevice final : public SoapySDR::Device {
 public:
  /// Claims `node` at `socket_path` (NodeStreamer). Throws std::runtime_error.
  RfsitlDevice(const std::string& socket_path, const external::DiscoveredNode& node,
               const NodeStreamer::Settings& settings);
  ~RfsitlDevice() override;
  RfsitlDevice(const RfsitlDevice&) = delete;
  RfsitlDevice& operator=(const RfsitlDevice&) = delete;

  /// True while a device of this process holds `node_id` of `socket_path`.
  /// find reports such a node as it did before the claim, because SoapySDR
  /// shares one device among the makes of a process only when find answers
  /// them identically (GNU Radio's Soapy source and sink each make one).
  static bool held_here(const std::string& socket_path, NodeId node_id);

  /// The device's label, the same in find's answer and getHardwareInfo()
  /// (SoapySDRUtil --find and --probe): "rfsitl <scenario> node <id>".
  static std::string label_of(const external::DiscoveredNode& node);

  std::string getDriverKey() const override { return "rfsitl"; }
  std::string getHardwareKey() const override { return "rfsitl"; }
  SoapySDR::Kwargs getHardwareInfo() const override;
  size_t getNumChannels(int direction) const override;
  bool getFullDuplex(int, size_t) const override { return true; }

  // Streams: at most one per direction, channel 0.
  std::vector<std::string> getStreamFormats(int direction, size_t channel) const override;
  std::string getNativeStreamFormat(int direction, size_t channel,
                                    double& full_scale) const override;
  SoapySDR::Stream* setupStream(int direction, const std::string& format,
                                const std::vector<size_t>& channels,
                                const SoapySDR::Kwargs& args) override;
  void closeStream(SoapySDR::Stream* stream) override;
  size_t getStreamMTU(SoapySDR::Stream* stream) const override;
  int activateStream(SoapySDR::Stream* stream, int flags, long long time_ns,
                     size_t num_elems) override;
  int deactivateStream(SoapySDR::Stream* stream, int flags, long long time_ns) override;
  int readStream(SoapySDR::Stream* stream, void* const* buffs, size_t num_elems, int& flags,
                 long long& time_ns, long timeout_us) override;
  int writeStream(SoapySDR::Stream* stream, const void* const* buffs, size_t num_elems, int& flags,
                  long long time_ns, long timeout_us) override;
  int readStreamStatus(SoapySDR::Stream* stream, size_t& chan_mask, int& flags, long long& time_ns,
                       long timeout_us) override;

  std::vector<std::string> listAntennas(int direction, size_t channel) const override;
  std::string getAntenna(int direction, size_t channel) const override;

  std::vector<std::string> listGains(int direction, size_t channel) const override;
  /// A value outside getGainRange() is clamped into it, with a warning in
  /// SoapySDR's log (as UHD does); NaN throws std::runtime_error.
  void setGain(int direction, size_t channel, double value) override;
  void setGain(int direction, size_t channel, const std::string& name, double value) override;
  double getGain(int direction, size_t channel) const override;
  double getGain(int direction, size_t channel, const std::string& name) const override;
  SoapySDR::Range getGainRange(int direction, size_t channel) const override;
  SoapySDR::Range getGainRange(int direction, size_t channel,
                               const std::string& name) const override;

  void setFrequency(int direction, size_t channel, double frequency,
                    const SoapySDR::Kwargs& args) override;
  void setFrequency(int direction, size_t channel, const std::string& name, double frequency,
                    const SoapySDR::Kwargs& args) override;
  double getFrequency(int direction, size_t channel) const override;
  double getFrequency(int direction, size_t channel, const std::string& name) const override;
  std::vector<std::string> listFrequencies(int direction, size_t channel) const override;
  SoapySDR::RangeList getFrequencyRange(int direction, size_t channel) const override;
  SoapySDR::RangeList getFrequencyRange(int direction, size_t channel,
                                        const std::string& name) const override;

  void setSampleRate(int direction, size_t channel, double rate) override;
  double getSampleRate(int direction, size_t channel) const override;
  std::vector<double> listSampleRates(int direction, size_t channel) const override;
  SoapySDR::RangeList getSampleRateRange(int direction, size_t channel) const override;
  double getBandwidth(int direction, size_t channel) const override;
  SoapySDR::RangeList getBandwidthRange(int direction, size_t channel) const override;

  /// Sensor "connected": "false" from the moment the emulator closed the
  /// connection until the device joined one again, so that an application
  /// whose stream blocks swallow errors (GNU Radio's) can notice that the
  /// emulator is gone.
  std::vector<std::string> listSensors() const override;
  SoapySDR::ArgInfo getSensorInfo(const std::string& key) const override;
  std::string readSensor(const std::string& key) const override;

  bool hasHardwareTime(const std::string& what) const override { return what.empty(); }
  /// The start of the emulator's latest tick, in ns. Before the first tick
  /// (the device was made a moment ago, or the emulator waits for its other
  /// external nodes) it waits for it, up to 10 s (kFirstTickTimeoutMs), so
  /// that the time is never a made-up 0; throws std::runtime_error saying
  /// why when none comes.
  long long getHardwareTime(const std::string& what) const override;
  void setHardwareTime(long long time_ns, const std::string& what) override;

 private:
  /// One direction's settings; index 0 = RX, 1 = TX.
  struct Path {
    double frequency_hz = 0.0;
    double gain_db = 0.0;  ///< the setting (GainControl), not the scale
    bool stream_open = false;
    SampleFormat format = SampleFormat::kCF32;
  };
  Path& path(int direction, size_t channel);
  const Path& path(int direction, size_t channel) const;
  Path& path_of(SoapySDR::Stream* stream);
  static const GainControl& gain_control(int direction);
  void apply(int direction);

  const std::string socket_path_;
  const external::DiscoveredNode node_;
  std::unique_ptr<NodeStreamer> streamer_;
  std::array<Path, 2> paths_;
  std::vector<cf32> scratch_;  // format conversions (one stream per direction)
  std::vector<cf32> tx_scratch_;
};

}  // namespace rfsitl::soapy
