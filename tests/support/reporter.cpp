// The "raykit" doctest reporter: one JSON object per line, written for the
// grader (tools/kitlib), not for people.
//
//   --list-test-cases  -> {"case": ..., "suite": ..., "lecture": ...} per case
//   a run              -> {"event": "start", "case": ...}
//                         {"event": "end", "case": ..., "status": ..., "messages": [...],
//                          "output": ..., "output_bytes": N}
//
// Every line is flushed at once. The student's code runs in another process
// (remote.hpp): a call that crashed, hung or threw there is recorded per case,
// and what the code printed comes back with the case. Status is one of pass,
// fail, not_started (a stub threw raykit::not_implemented), threw, crashed,
// timed_out, grader_error (no verdict: the judge itself crashed or threw, with
// "fault" saying so; the step is not graded, raykit/faults.py).

#include <doctest/doctest.h>

#include <cstddef>

#include <ostream>
#include <string>
#include <vector>

#include "case_figure.hpp"
#include "remote.hpp"

namespace {

// Whether the exception leaving the current case came from a call of the student's code (a proxy's
// CallFailed: it crashed, hung, threw or sent back what cannot be read) or from the judge's own code.
bool from_a_call = false;

std::string json_string(const char* text) {
    std::string out = "\"";
    for (const char* p = text ? text : ""; *p; ++p) {
        const unsigned char ch = static_cast<unsigned char>(*p);
        switch (ch) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            default:
                if (ch < 0x20) {
                    static const char hex[] = "0123456789abcdef";
                    out += "\\u00";
                    out += hex[ch >> 4];
                    out += hex[ch & 15];
                } else {
                    out += static_cast<char>(ch);
                }
        }
    }
    return out + "\"";
}

class RaykitReporter : public doctest::IReporter {
public:
    explicit RaykitReporter(const doctest::ContextOptions& options) : out_(*options.cout) {}

    void report_query(const doctest::QueryData& query) override {
        for (unsigned i = 0; i < query.num_data; ++i) {
            const doctest::TestCaseData& tc = *query.data[i];
            out_ << "{\"case\": " << json_string(tc.m_name)
                 << ", \"suite\": " << json_string(tc.m_test_suite)
                 << ", \"lecture\": " << json_string(tc.m_description) << "}\n";
        }
        out_.flush();
    }

    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats&) override {
        raykit::remote::shutdown();
        out_.flush();
    }

    void test_case_start(const doctest::TestCaseData& tc) override {
        current_ = &tc;
        messages_.clear();
        exception_.clear();
        not_started_ = crashed_ = false;
        from_a_call = false;
        raykit::remote::begin_case(tc.m_test_suite ? tc.m_test_suite : "");
        raykit::figure::begin_case();
        out_ << "{\"event\": \"start\", \"case\": " << json_string(tc.m_name) << "}\n";
        out_.flush();
    }
    void test_case_reenter(const doctest::TestCaseData&) override {}

    void test_case_exception(const doctest::TestCaseException& e) override {
        exception_ = e.error_string.c_str();
        crashed_ = e.is_crash;
        not_started_ = exception_.find("raykit::not_implemented") != std::string::npos;
        if (crashed_) {
            // The process is about to die: say so while we still can. The student's code runs in
            // the answers process, never here, so this is the judge's own crash: no verdict, the
            // grader's fault (the case is not graded, raykit/faults.py), said as data.
            fault_ = "the kit's test program crashed (" + exception_ + ")";
            write_end("grader_error");
        }
    }

    void test_case_end(const doctest::CurrentTestCaseStats& stats) override {
        if (crashed_) return;
        record_ = raykit::remote::end_case();
        const char* status = "pass";
        if (record_.incident.status == "crashed" || record_.incident.status == "timed_out" ||
            record_.incident.status == "grader_error") {
            // The call that failed is named in the incident's message; the
            // exception that carried it out of the case adds nothing.
            status = record_.incident.status.c_str();
            messages_.insert(messages_.begin(), record_.incident.message);
            exception_.clear();
        } else if (not_started_) {
            status = "not_started";
        } else if (record_.incident.status == "threw") {
            status = "threw";
            if (exception_.find(record_.incident.message) == std::string::npos)
                messages_.insert(messages_.begin(), record_.incident.message);
        } else if (!exception_.empty() && from_a_call) {
            status = "threw";          // a call's answer the grader cannot read: the student's
        } else if (!exception_.empty()) {
            // No call behind it: the judge's own code threw. No verdict, the grader's fault.
            status = "grader_error";
            fault_ = "the kit's test program threw (" + exception_ + ")";
        } else if (stats.failure_flags != 0 || stats.numAssertsFailedCurrentTest > 0) {
            // failure_flags, not testCaseSuccess: the latter is new in doctest 2.4.6 and Debian 11
            // ships 2.4.5. They differ only for may_fail/should_fail cases, which the kit has none of.
            status = "fail";
        }
        write_end(status);
    }

    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}

    void log_assert(const doctest::AssertData& a) override {
        if (!a.m_failed) return;
        std::string text = std::string("CHECK(") + a.m_expr + ")";
        if (a.m_threw) {
            text += " threw: " + std::string(a.m_exception.c_str());
            if (text.find("raykit::not_implemented") != std::string::npos) not_started_ = true;
        } else {
            text += " is false, with values " + std::string(a.m_decomp.c_str());
        }
        messages_.push_back(text);
    }

    void log_message(const doctest::MessageData& m) override {
        if (m.m_severity & doctest::assertType::is_warn) return;
        messages_.push_back(m.m_string.c_str());
    }

    void test_case_skipped(const doctest::TestCaseData&) override {}

private:
    void write_end(const char* status) {
        out_ << "{\"event\": \"end\", \"case\": " << json_string(current_ ? current_->m_name : "")
             << ", \"status\": \"" << status << "\", \"messages\": [";
        bool first = true;
        for (const std::string& m : messages_) {
            out_ << (first ? "" : ", ") << json_string(m.c_str());
            first = false;
        }
        if (!exception_.empty()) {
            out_ << (first ? "" : ", ") << json_string(exception_.c_str());
        }
        out_ << "], \"output\": " << json_string(record_.output.c_str())
             << ", \"output_bytes\": " << record_.output_bytes;
        // What went wrong beyond a wrong answer, as data (the class report groups crashes by it).
        if (!record_.incident.status.empty() && !record_.incident.function.empty())
            out_ << ", \"incident\": {\"function\": " << json_string(record_.incident.function.c_str())
                 << ", \"signal\": " << json_string(record_.incident.signal.c_str()) << "}";
        if (!fault_.empty()) out_ << ", \"fault\": " << json_string(fault_.c_str());
        // The geometry of the first failing check, for its picture (case_figure.hpp).
        if (!raykit::figure::record().empty()) out_ << ", \"figure\": " << raykit::figure::record();
        out_ << "}\n";
        out_.flush();
        record_ = {};
    }

    std::ostream& out_;
    const doctest::TestCaseData* current_ = nullptr;
    std::vector<std::string> messages_;
    std::string exception_;
    std::string fault_;         // the judge's own crash, when it is one
    bool not_started_ = false;
    bool crashed_ = false;
    raykit::remote::CaseRecord record_;
};

}  // namespace

REGISTER_REPORTER("raykit", 1, RaykitReporter);

// Marks an exception out of a case as a call's (see from_a_call); its text as doctest would give it.
REGISTER_EXCEPTION_TRANSLATOR(const raykit::remote::CallFailed& e) {
    from_a_call = true;
    return doctest::String(e.what());
}
