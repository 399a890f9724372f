#pragma once
// Records another component's published samples at its own rate (for example
// 60 Hz next to a 1 kHz haptic loop) into recording.<path>.csv. It reads
// through a channel, so it may run in its own thread without slowing the source.
#include <vector>

#include "framework/channels/Channel.h"
#include "framework/core/Component.h"
#include "framework/core/SampleSource.h"

namespace trephine {

class Recorder final : public Component {
 public:
  static constexpr std::string_view kTypeName = "Recorder";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;

 private:
  std::string fileName() const;
  size_t rowWidth() const;
  Link<SampleSource> l_source{
      this,
      "source",
      {.help = "Component whose samples are recorded (read through a channel)", .required = true, .initOnly = true}};
  RateField d_rate{this, 60.0, "Sampling rate of the recording"};
  Field<std::string> d_file{
      this, "file", "", {.help = "Output file name in the run directory (default recording.<path with / as .>.csv)"}};

  std::optional<ChannelReader<Sample>> m_reader;
  std::vector<std::string> m_columns;
  // Rows stored flat: t, source_t, then one value per column (only the columns in use).
  std::vector<double> m_rows;
  size_t m_rowCapacity = 0;
  size_t m_size = 0;
};

}  // namespace trephine
