// SPDX-License-Identifier: BSD-2-Clause
#include "database/json_stream.h"

#include <iterator>
#include <utility>
#include <vector>

namespace svc {

namespace {

using json = nlohmann::json;

// An input iterator over a stream buffer that counts the bytes consumed: the parser's
// position in the file, which tells where an element begins and ends.
class CountingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = char;

  CountingIterator() = default;
  CountingIterator(std::streambuf* buffer, uint64_t* consumed) : buffer_(buffer), consumed_(consumed) {}

  char operator*() const { return std::char_traits<char>::to_char_type(buffer_->sgetc()); }
  CountingIterator& operator++() {
    buffer_->sbumpc();
    ++*consumed_;
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const CountingIterator& other) const { return at_end() == other.at_end(); }
  bool operator!=(const CountingIterator& other) const { return !(*this == other); }

 private:
  bool at_end() const { return buffer_ == nullptr || buffer_->sgetc() == std::char_traits<char>::eof(); }

  std::streambuf* buffer_ = nullptr;
  uint64_t* consumed_ = nullptr;
};

// Builds one JSON value from SAX events. Duplicate keys keep the last value, as
// nlohmann::json::parse does.
class JsonBuilder {
 public:
  void value(json v) { place(std::move(v)); }
  void open(json container) { open_.push_back(place(std::move(container))); }
  void close() { open_.pop_back(); }
  void key(std::string name) { key_ = std::move(name); }
  json& root() { return root_; }
  void reset() {
    root_ = json();
    open_.clear();
  }

 private:
  json* place(json v) {
    if (open_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& parent = *open_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return &parent.back();
    }
    json& slot = parent[key_];
    slot = std::move(v);
    return &slot;
  }

  json root_;
  std::vector<json*> open_;  // the containers still open, outermost first
  std::string key_;
};

// Routes events: inside the streamed key's top-level array (depth 2 and below) to the
// element being built, everything else to the outline.
class StreamingSax final : public nlohmann::json_sax<json> {
 public:
  StreamingSax(const uint64_t* consumed, const std::string& array_key, int streamed_array,
               const JsonElementHandler& element, StreamedJson* out)
      : consumed_(consumed), array_key_(array_key), streamed_array_(streamed_array), element_(element), out_(out) {}

  bool null() override { return scalar(json(nullptr)); }
  bool boolean(bool v) override { return scalar(json(v)); }
  bool number_integer(number_integer_t v) override { return scalar(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return scalar(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return scalar(json(v)); }
  bool string(string_t& v) override { return scalar(json(std::move(v))); }
  bool binary(binary_t&) override { return true; }  // not produced by JSON text
  bool start_object(std::size_t) override { return open(json::object(), false); }
  bool start_array(std::size_t) override { return open(json::array(), true); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& name) override {
    if (in_element()) {
      if (streaming()) element_builder_.key(std::move(name));
      return true;
    }
    if (depth_ == 1) top_key_ = name;
    outline_builder_.key(std::move(name));
    return true;
  }
  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& ex) override {
    out_->syntax_ok = false;
    out_->syntax_error.offset = position;
    out_->syntax_error.last_token = last_token;
    out_->syntax_error.message = ex.what();
    out_->syntax_error.has_position = dynamic_cast<const json::parse_error*>(&ex) != nullptr;
    return false;
  }

  json take_outline() { return std::move(outline_builder_.root()); }

 private:
  // Events at depth 2 or deeper while the streamed key's array is open belong to one of
  // its elements.
  bool in_element() const { return in_array_ && depth_ >= 2; }
  bool streaming() const { return out_->array_count == streamed_array_; }

  bool scalar(json v) {
    if (!in_element()) {
      outline_builder_.value(std::move(v));
      return true;
    }
    if (!streaming()) return depth_ == 2 ? element_done(0) : true;
    element_builder_.value(std::move(v));
    return depth_ == 2 ? element_done(*consumed_) : true;
  }

  bool open(json container, bool is_array) {
    if (in_element()) {
      if (depth_ == 2) element_start_ = *consumed_ - 1;  // the bracket just read
      if (streaming()) element_builder_.open(std::move(container));
    } else {
      outline_builder_.open(std::move(container));
      if (depth_ == 1 && is_array && top_key_ == array_key_) {
        in_array_ = true;
        ++out_->array_count;
        out_->last_array_size = 0;
      }
    }
    ++depth_;
    return true;
  }

  bool close() {
    --depth_;
    if (!in_element()) {
      outline_builder_.close();
      if (depth_ == 1) in_array_ = false;
      return true;
    }
    if (streaming()) element_builder_.close();
    return depth_ == 2 ? element_done(*consumed_) : true;
  }

  // An element of the array ended at byte `end`.
  bool element_done(uint64_t end) {
    ++out_->last_array_size;
    if (!streaming()) return true;
    const bool go_on = element_(element_builder_.root(), element_start_, end - element_start_);
    element_builder_.reset();
    if (!go_on) out_->stopped = true;
    return go_on;
  }

  const uint64_t* consumed_;
  const std::string& array_key_;
  const int streamed_array_;
  const JsonElementHandler& element_;
  StreamedJson* out_;
  JsonBuilder outline_builder_;
  JsonBuilder element_builder_;
  int depth_ = 0;  // containers open
  std::string top_key_;
  bool in_array_ = false;
  uint64_t element_start_ = 0;
};

}  // namespace

StreamedJson stream_json(std::istream& in, const std::string& array_key, int streamed_array,
                         const JsonElementHandler& element) {
  StreamedJson out;
  uint64_t consumed = 0;
  StreamingSax sax(&consumed, array_key, streamed_array, element, &out);
  const CountingIterator first(in.rdbuf(), &consumed);
  json::sax_parse(first, CountingIterator(), &sax);
  out.outline = sax.take_outline();
  return out;
}

std::pair<uint64_t, uint64_t> line_and_column(std::istream& in, uint64_t offset) {
  in.clear();
  in.seekg(0);
  uint64_t line = 1, line_start = 0, read = 0;
  std::streambuf* buffer = in.rdbuf();
  for (; read < offset; ++read) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) break;
    if (c == '\n') {
      ++line;
      line_start = read + 1;
    }
  }
  return {line, read - line_start + 1};
}

}  // namespace svc
