// Checks of an exception's message: that a call throws, of which type, saying what.
#pragma once

#include <exception>
#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

namespace snert::test {

// Whether `text` contains `part`.
bool contains(const std::string& text, const std::string& part);

// The message of the exception of type E (or a subclass) that `call` throws; a test failure,
// and "", when it throws nothing. Another exception type propagates (GoogleTest reports it).
template <class E = std::exception, class F> std::string error_of(F&& call) {
    try {
        call();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an exception";
    return "";
}

// A test failure for each of `parts` that `message` does not contain.
void expect_contains(const std::string& message, std::initializer_list<std::string> parts);

// `call` throws E (or a subclass) whose message contains every one of `parts`.
template <class E = std::exception, class F>
void expect_error(F&& call, std::initializer_list<std::string> parts) {
    expect_contains(error_of<E>(static_cast<F&&>(call)), parts);
}

} // namespace snert::test
