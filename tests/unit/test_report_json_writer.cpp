// JsonWriter: escaping, UTF-8 repair, number round-trips, layout, misuse.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <locale>
#include <stdexcept>
#include <string>

#include "core/report/json_writer.h"

namespace MBX_UNITY_ID {

using mbx::JsonWriter;

namespace {

std::string json_of(std::string_view s) {
    JsonWriter w;
    w.value(s);
    return w.str();
}

std::string json_of(double d) {
    JsonWriter w;
    w.value(d);
    return w.str();
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

const std::string kFffd = "\xEF\xBF\xBD";

}  // namespace

TEST_CASE("json: quotes, backslashes and control characters are escaped") {
    CHECK(json_of("plain") == "\"plain\"");
    CHECK(json_of("say \"hi\"") == "\"say \\\"hi\\\"\"");
    CHECK(json_of("C:\\parts\\crank") == "\"C:\\\\parts\\\\crank\"");
    CHECK(json_of("a\nb\tc\rd\be\ff") == "\"a\\nb\\tc\\rd\\be\\ff\"");
    CHECK(json_of(std::string_view("\x01\x1f\x7f/", 4)) == "\"\\u0001\\u001f\x7f/\"");
    CHECK(json_of(std::string_view("nul\0byte", 8)) == "\"nul\\u0000byte\"");
    CHECK(json_of("") == "\"\"");
}

TEST_CASE("json: valid UTF-8 passes through unchanged") {
    const std::string s = "h\xC3\xA9llo \xE2\x82\xAC \xF0\x9D\x84\x9E \xE4\xB8\xAD\xE6\x96\x87";  // é € 𝄞 中文
    CHECK(json_of(s) == "\"" + s + "\"");
    // Boundaries of the valid ranges.
    const std::string edges = "\xC2\x80\xDF\xBF\xE0\xA0\x80\xED\x9F\xBF\xEE\x80\x80\xF0\x90\x80\x80\xF4\x8F\xBF\xBF";
    CHECK(json_of(edges) == "\"" + edges + "\"");
}

TEST_CASE("json: ill-formed UTF-8 becomes U+FFFD, one per maximal subpart") {
    CHECK(json_of("a\xFF" "b") == "\"a" + kFffd + "b\"");               // never a lead byte
    CHECK(json_of("\x80") == "\"" + kFffd + "\"");                      // stray continuation
    CHECK(json_of("\xC3") == "\"" + kFffd + "\"");                      // truncated at the end
    CHECK(json_of("\xE2\x82x") == "\"" + kFffd + "x\"");                // truncated in the middle
    CHECK(json_of("\xC0\xAF") == "\"" + kFffd + kFffd + "\"");          // overlong '/'
    CHECK(json_of("\xED\xA0\x80") == "\"" + kFffd + kFffd + kFffd + "\"");  // UTF-16 surrogate
    CHECK(json_of("\xF4\x90\x80\x80") == "\"" + kFffd + kFffd + kFffd + kFffd + "\"");  // > U+10FFFF
    CHECK(json_of("\xF0\x9D\x84") == "\"" + kFffd + "\"");              // 3 of 4 bytes
    // Latin-1 text, as some CAD systems deliver it.
    CHECK(json_of("Stra\xDF" "e") == "\"Stra" + kFffd + "e\"");
}

TEST_CASE("json: numbers round-trip exactly through strtod") {
    const double values[] = {0.1,
                             1e-300,
                             -0.0,
                             0.0,
                             5e-324,
                             2.2250738585072014e-308,
                             std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::max(),
                             1.0 / 3.0,
                             0.1 + 0.2,
                             123456789012345678.0,
                             1e21,
                             -2.5,
                             9.81};
    for (double v : values) {
        const std::string text = json_of(v);
        CAPTURE(text);
        char* end = nullptr;
        const double back = std::strtod(text.c_str(), &end);
        CHECK(*end == '\0');
        CHECK(same_bits(back, v));
    }
    CHECK(json_of(0.1) == "0.1");
    CHECK(json_of(1e-300) == "1e-300");
    CHECK(json_of(-0.0) == "-0");
    CHECK(json_of(2.0) == "2");
}

TEST_CASE("json: non-finite numbers are written as null") {
    CHECK(json_of(std::numeric_limits<double>::quiet_NaN()) == "null");
    CHECK(json_of(std::numeric_limits<double>::infinity()) == "null");
    CHECK(json_of(-std::numeric_limits<double>::infinity()) == "null");
}

namespace {
// A decimal comma, as in a German locale; the writer must not care.
struct CommaPunct : std::numpunct<char> {
    char do_decimal_point() const override { return ','; }
};
}  // namespace

TEST_CASE("json: numbers ignore the global locale") {
    const std::locale previous = std::locale::global(std::locale(std::locale::classic(), new CommaPunct));
    const std::string text = json_of(1.5);
    std::locale::global(previous);
    CHECK(text == "1.5");
}

TEST_CASE("json: integers and booleans") {
    JsonWriter w;
    w.begin_array(JsonWriter::Layout::Inline);
    w.value(std::numeric_limits<long long>::min()).value(std::numeric_limits<unsigned long long>::max());
    w.value(0).value(-7).value(std::size_t{42}).value(true).value(false).null();
    w.value(static_cast<const char*>(nullptr));
    w.end_array();
    CHECK(w.str() == "[-9223372036854775808, 18446744073709551615, 0, -7, 42, true, false, null, null]");
}

TEST_CASE("json: pretty layout, inline containers and key order") {
    JsonWriter w;
    w.begin_object();
    w.member("z", 1);
    w.member("a", "x");
    w.key("empty_object").begin_object().end_object();
    w.key("empty_array").begin_array().end_array();
    const double v[3] = {1, 0.5, -0.0};
    w.key("vec").number_array(v, 3);
    w.key("list").begin_array();
    w.value(1);
    w.begin_object(JsonWriter::Layout::Inline).member("k", 2).key("n").begin_array().value(3).end_array().end_object();
    w.end_array();
    w.end_object();
    CHECK(w.complete());
    CHECK(w.str() ==
          "{\n"
          "  \"z\": 1,\n"
          "  \"a\": \"x\",\n"
          "  \"empty_object\": {},\n"
          "  \"empty_array\": [],\n"
          "  \"vec\": [1, 0.5, -0],\n"
          "  \"list\": [\n"
          "    1,\n"
          "    {\"k\": 2, \"n\": [3]}\n"
          "  ]\n"
          "}");
}

TEST_CASE("json: keys are escaped like strings") {
    JsonWriter w;
    w.begin_object(JsonWriter::Layout::Inline).member("a\"b\n", 1).end_object();
    CHECK(w.str() == "{\"a\\\"b\\n\": 1}");
}

TEST_CASE("json: misuse is reported, not silently written") {
    {
        JsonWriter w;
        w.begin_object();
        CHECK_THROWS_AS(w.value(1), std::logic_error);  // no key
    }
    {
        JsonWriter w;
        w.begin_array();
        CHECK_THROWS_AS(w.key("k"), std::logic_error);  // key in an array
        CHECK_THROWS_AS(w.end_object(), std::logic_error);
    }
    {
        JsonWriter w;
        w.begin_object().key("k");
        CHECK_THROWS_AS(w.key("again"), std::logic_error);
        CHECK_THROWS_AS(w.end_object(), std::logic_error);  // dangling key
    }
    {
        JsonWriter w;
        w.value(1);
        CHECK(w.complete());
        CHECK_THROWS_AS(w.value(2), std::logic_error);  // second document
        CHECK_THROWS_AS(w.end_array(), std::logic_error);
    }
}

TEST_CASE("json: take() empties the writer for reuse") {
    JsonWriter w;
    w.value("first");
    CHECK(w.take() == "\"first\"");
    CHECK_FALSE(w.complete());
    w.value(2);
    CHECK(w.str() == "2");
}
}  // namespace MBX_UNITY_ID
