// Range checks for numbers on the demos' command lines (CLI11), with messages that name the
// value and the range.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace btdemo {

template <class Number>
std::string rangeText(Number lo, Number hi) {
    std::ostringstream out;
    out << '[' << lo << ", " << hi << ']';
    return out.str();
}

// A decimal integer in [lo, hi]. Pass it to Option::transform(), not check(): it rewrites the
// text to plain decimal, since CLI11 2.1 on its own reads 010 as octal 8 and 0x10 as 16.
inline CLI::Validator integerIn(long lo, long hi) {
    const std::string range = rangeText(lo, hi);
    auto check = [lo, hi, range](std::string& text) -> std::string {
        size_t used = 0;
        long value = 0;
        try {
            value = std::stol(text, &used, 10);
        } catch (const std::exception&) {
            used = 0;
        }
        if (text.empty() || used != text.size() || value < lo || value > hi)
            return "'" + text + "' is not an integer in " + range;
        text = std::to_string(value);
        return "";
    };
    return CLI::Validator(check, "INT in " + range);
}

// A number in [lo, hi]. CLI::Range would let NaN through.
inline CLI::Validator numberIn(double lo, double hi) {
    const std::string range = rangeText(lo, hi);
    auto check = [lo, hi, range](const std::string& text) -> std::string {
        size_t used = 0;
        double value = 0;
        try {
            value = std::stod(text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (text.empty() || used != text.size() || !(value >= lo && value <= hi))
            return "'" + text + "' is not a number in " + range;
        return "";
    };
    return CLI::Validator(check, "FLOAT in " + range);
}

// Parses a demo's command line. Returns the exit status when the program should stop here: 0
// after --help, 2 (with a message naming the program) after a bad argument.
inline std::optional<int> parseOrExitCode(CLI::App& app, int argc, char** argv, const char* program) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "%s: %s\nRun %s --help for the options.\n", program, e.what(), program);
        return 2;
    }
    return std::nullopt;
}

}  // namespace btdemo
