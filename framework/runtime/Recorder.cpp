#include "framework/runtime/Recorder.h"

#include <fstream>

#include "framework/core/AtomicFile.h"
#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"

namespace trephine {

void Recorder::init(InitContext& context) {
  m_columns = l_source->sampleColumns();
  if (m_columns.size() > kMaxSampleValues) {
    context.error(*this, "source publishes " + std::to_string(m_columns.size()) + " values, at most " +
                             std::to_string(kMaxSampleValues) + " are supported");
    m_columns.resize(kMaxSampleValues);
  }
  m_reader = context.channels().subscribe<Sample>(*l_source.boundComponent(), kSampleChannel);
}

size_t Recorder::rowWidth() const { return 2 + m_columns.size(); }

void Recorder::prepare(const RunPlan& plan) {
  m_rowCapacity = plan.callsAt(rateHz());
  m_rows.assign(m_rowCapacity * rowWidth(), 0.0);
  m_size = 0;
}

void Recorder::tick(const TickContext& context) {
  m_reader->fetch();
  if (m_size >= m_rowCapacity) return;
  const Sample& sample = m_reader->read();
  double* row = &m_rows[m_size++ * rowWidth()];
  row[0] = context.t;
  row[1] = sample.t;
  for (size_t k = 0; k < m_columns.size(); ++k) row[2 + k] = sample.values[k];
}

std::string Recorder::fileName() const {
  return d_file->empty() ? FinishContext::defaultFileName("recording", *this) : d_file.value();
}

void Recorder::declareOutputs(std::vector<OutputFile>& outputs) const {
  outputs.push_back({fileName(), d_file.isSet() ? &d_file : nullptr});
}

void Recorder::finish(FinishContext& context) {
  if (context.outputDirectory().empty()) return;
  const std::string name = fileName();
  if (!context.claimOutput(*this, name)) return;
  try {
    writeFileAtomically(context.outputDirectory() / name, [&](std::ostream& out) {
      out << "t,source_t";
      for (const std::string& c : m_columns) out << "," << c;
      out << "\n";
      for (size_t i = 0; i < m_size; ++i) {
        const double* row = &m_rows[i * rowWidth()];
        for (size_t k = 0; k < rowWidth(); ++k) out << (k ? "," : "") << formatDouble(row[k]);
        out << "\n";
      }
    });
  } catch (const FileWriteError& e) {
    context.error(*this, e.what());
  }
}

void Recorder::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"rows", static_cast<double>(m_size)});
}

}  // namespace trephine
