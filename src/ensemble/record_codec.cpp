#include "ensemble/record_codec.hpp"

#include <cstring>
#include <stdexcept>

namespace treedyn::ensemble {
namespace {

template <class T>
void put(std::vector<char>& b, const T& v) {
  const auto* p = reinterpret_cast<const char*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}

void put_doubles(std::vector<char>& b, const std::vector<double>& v) {
  put(b, static_cast<std::uint64_t>(v.size()));
  const auto* p = reinterpret_cast<const char*>(v.data());
  b.insert(b.end(), p, p + v.size() * sizeof(double));
}

class Reader {
 public:
  explicit Reader(const std::vector<char>& b) : b_(b) {}
  bool done() const { return at_ == b_.size(); }
  template <class T>
  T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::vector<double> doubles() {
    const auto n = get<std::uint64_t>();
    if (n > (b_.size() - at_) / sizeof(double)) throw std::runtime_error("sample record buffer truncated");
    std::vector<double> v(n);
    if (n > 0) std::memcpy(v.data(), b_.data() + at_, n * sizeof(double));  // empty: data() may be null
    at_ += n * sizeof(double);
    return v;
  }
  std::string text() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s(b_.data() + at_, n);
    at_ += n;
    return s;
  }

 private:
  void need(std::size_t n) const {
    if (n > b_.size() - at_) throw std::runtime_error("sample record buffer truncated");
  }
  const std::vector<char>& b_;
  std::size_t at_ = 0;
};

}  // namespace

void append_record(const ensemble::SampleRecord& r, std::vector<char>& b) {
  put(b, r.index);
  put(b, static_cast<std::int32_t>(r.status));
  put(b, r.time_reached);
  for (const IntegratorStatField& f : kIntegratorStatFields) put(b, r.stats.*f.member);
  put(b, static_cast<std::uint64_t>(r.reason.size()));
  b.insert(b.end(), r.reason.begin(), r.reason.end());
  put_doubles(b, r.inputs);
  put_doubles(b, r.reductions);
  put_doubles(b, r.responses);
  put_doubles(b, r.final_state);
  put_doubles(b, r.trajectory);
}

std::vector<ensemble::SampleRecord> read_records(const std::vector<char>& buffer) {
  std::vector<ensemble::SampleRecord> out;
  Reader in(buffer);
  while (!in.done()) {
    ensemble::SampleRecord r;
    r.index = in.get<std::uint64_t>();
    const auto status = in.get<std::int32_t>();
    if (status < 0 || status > static_cast<std::int32_t>(ensemble::SampleStatus::not_run))
      throw std::runtime_error("sample record with an unknown status");
    r.status = static_cast<ensemble::SampleStatus>(status);
    r.time_reached = in.get<double>();
    for (const IntegratorStatField& f : kIntegratorStatFields) r.stats.*f.member = in.get<long>();
    r.reason = in.text();
    r.inputs = in.doubles();
    r.reductions = in.doubles();
    r.responses = in.doubles();
    r.final_state = in.doubles();
    r.trajectory = in.doubles();
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace treedyn::ensemble
