#include "io/config/table_keys.hpp"

namespace codesign::io {

void KeyReader::window(const config::Key& ks, const config::Key& ke, std::optional<std::int64_t>& start,
                       std::optional<std::int64_t>& end, Range<std::int64_t> r) {
  const std::string s(ks.name), e(ke.name);
  if (!t_.has(s) && !t_.has(e)) {
    t_.integer(s, 0, r);  // marks both as read so finish() accepts neither being present
    t_.integer(e, 0, r);
    return;
  }
  if (!t_.has(s) || !t_.has(e)) t_.fail(t_.has(s) ? e : s, "missing; " + s + " and " + e + " must be given together");
  start = t_.integer(s, 0, r);
  end = t_.integer(e, 0, r);
  if (*end <= *start) t_.fail(e, "must be greater than " + s + " (" + std::to_string(*start) + ")");
}

}  // namespace codesign::io
