// Fault injection on a byte stream: every fault is random but repeatable from the seed.
#include "host/transport/fault_transport.h"

#include <cstdlib>
#include <stdexcept>
#include <thread>
#include <vector>

namespace dg::host {

FaultSpec parse_fault_spec(const std::string& text) {
  FaultSpec spec;
  size_t start = 0;
  while (start < text.size()) {
    size_t comma = text.find(',', start);
    if (comma == std::string::npos) comma = text.size();
    const std::string pair = text.substr(start, comma - start);
    start = comma + 1;
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("fault option '" + pair + "' is not key=value");
    const std::string key = pair.substr(0, eq), value = pair.substr(eq + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || v < 0) throw std::invalid_argument("fault option '" + pair + "': not a number >= 0");
    if (key == "corrupt") spec.corrupt = v;
    else if (key == "drop") spec.drop = v;
    else if (key == "dup") spec.duplicate = v;
    else if (key == "outages") spec.outages = static_cast<int>(v);
    else if (key == "outage_ms") spec.outage_ms = static_cast<int>(v);
    else if (key == "every") spec.outage_every = static_cast<int>(v);
    else if (key == "delay") spec.delay = v;
    else if (key == "delay_ms") spec.delay_ms = static_cast<int>(v);
    else if (key == "disconnects") spec.disconnects = static_cast<int>(v);
    else if (key == "seed") spec.seed = static_cast<unsigned>(v);
    else throw std::invalid_argument("unknown fault option '" + key + "' (corrupt, drop, dup, delay, delay_ms, outages, outage_ms, every, disconnects, seed)");
  }
  if (spec.corrupt > 1 || spec.drop > 1 || spec.duplicate > 1 || spec.delay > 1) throw std::invalid_argument("fault probabilities must be 0..1");
  return spec;
}

FaultTransport::FaultTransport(std::unique_ptr<Transport> inner, const FaultSpec& spec)
    : inner_(std::move(inner)), spec_(spec), rng_(spec.seed), outages_left_(spec.outages), disconnects_left_(spec.disconnects) {}

bool FaultTransport::chance(double p) { return p > 0 && std::uniform_real_distribution<double>(0, 1)(rng_) < p; }

bool FaultTransport::in_outage() { return std::chrono::steady_clock::now() < outage_end_; }

void FaultTransport::disconnect() {
  inner_->disconnect();
  disconnected_ = true;
}

void FaultTransport::reconnect() {
  inner_->reconnect();
  disconnected_ = false;
}

void FaultTransport::write(const uint8_t* data, size_t size) {
  if (disconnected_) throw TransportError(describe() + ": the cable is pulled (fault injection)");
  ++writes_;
  // Disconnects fall halfway between outages.
  const uint64_t every = static_cast<uint64_t>(spec_.outage_every);
  if (disconnects_left_ > 0 && every > 0 && writes_ % every == every / 2) {
    --disconnects_left_;
    ++counters_.disconnects;
    disconnect();
    throw TransportError(describe() + ": cable pulled (fault injection)");
  }
  if (outages_left_ > 0 && spec_.outage_every > 0 && writes_ % static_cast<uint64_t>(spec_.outage_every) == 0) {
    --outages_left_;
    ++counters_.outages;
    outage_end_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(spec_.outage_ms);
  }
  if (in_outage() || chance(spec_.drop)) {
    ++counters_.dropped;
    return;
  }
  if (chance(spec_.delay)) {
    ++counters_.delayed;
    std::this_thread::sleep_for(std::chrono::milliseconds(spec_.delay_ms));
  }
  std::vector<uint8_t> bytes(data, data + size);
  for (uint8_t& b : bytes) {
    if (chance(spec_.corrupt)) {
      b ^= static_cast<uint8_t>(1 + rng_() % 255);
      ++counters_.corrupted;
    }
  }
  inner_->write(bytes.data(), bytes.size());
  if (chance(spec_.duplicate)) {
    ++counters_.duplicated;
    inner_->write(bytes.data(), bytes.size());
  }
}

size_t FaultTransport::read(uint8_t* data, size_t capacity, int timeout_ms) {
  if (disconnected_) throw TransportError(describe() + ": the cable is pulled (fault injection)");
  const size_t n = inner_->read(data, capacity, timeout_ms);
  // During an outage the device's bytes are lost on the dead line.
  if (n > 0 && (in_outage() || chance(spec_.drop))) {
    ++counters_.dropped;
    return 0;
  }
  for (size_t i = 0; i < n; ++i) {
    if (chance(spec_.corrupt)) {
      data[i] ^= static_cast<uint8_t>(1 + rng_() % 255);
      ++counters_.corrupted;
    }
  }
  return n;
}

std::string FaultTransport::describe() const { return inner_->describe() + " (with faults)"; }

}  // namespace dg::host
