// snert: Marching Cubes and SNERT side by side. The subcommands are declared with CLI11
// (commands.h); with none, the app opens where it is built in.
//
// Exit codes: 0 success (and --help, --version); 2 bad input or usage (InputError, a
// CLI::ParseError), with one line "snert COMMAND: message" on stderr; 1 anything else
// ("internal error"), or a cancelled run.
#include <exception>
#include <iostream>

#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "freed_memory.h"
#include "core/input_error.h"
#include "core/progress.h"

#ifndef SNERT_VERSION
#define SNERT_VERSION "unknown"
#endif

namespace {

// One line: CLI11 and the libraries may put several into a message.
std::string one_line(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app("snert: Marching Cubes and SNERT side by side", "snert");
    app.set_version_flag("--version", "snert " SNERT_VERSION, "print the version and exit");
    app.require_subcommand(0, 1);
    app.footer("inputs: phantom:NAME or a volume file, DICOM folder or raw data; run `snert "
               "COMMAND --help` for the options of a command\n");

    std::map<std::string, snert::cli::Runner> runners;
    runners["table1"] = snert::cli::add_table1(app);
    runners["compare"] = snert::cli::add_compare(app);
    runners["export"] = snert::cli::add_export(app);
    runners["bench"] = snert::cli::add_bench(app);
#ifdef SNERT_HAVE_RENDER
    runners["render"] = snert::cli::add_render(app);
#endif
#ifdef SNERT_HAVE_APP
    runners["gui"] = snert::cli::add_gui(app);
#endif
    app.add_subcommand("version", "print the version and exit");

    // The command named on the line, for the messages ("snert compare: ...").
    std::string command;
    if (argc > 1 && argv[1][0] != '-') command = argv[1];
    const std::string prefix = command.empty() ? "snert: " : "snert " + command + ": ";
    if (!command.empty() && command != "version" && command != "help" && !runners.count(command)) {
        std::cerr << "snert " << command << ": unknown command '" << command
                  << "' (see snert --help)\n";
        return 2;
    }
    if (command == "help") {
        std::cout << app.help();
        return 0;
    }

    try {
        app.parse(argc, argv);
        if (command == "version") {
            std::cout << "snert " SNERT_VERSION "\n";
            return 0;
        }
        // Batch commands return what they free; the app keeps it (freed_memory.cpp says why).
        snert::cli::set_freed_memory(command.empty() || command == "gui"
                                         ? snert::cli::FreedMemory::Kept
                                         : snert::cli::FreedMemory::Returned);
        if (command.empty() || command == "gui")
            snert::cli::reserve_heap_on_huge_pages(std::size_t(512) << 20);
        if (command.empty()) {
#ifdef SNERT_HAVE_APP
            return runners.at("gui")();
#else
            std::cerr << app.help();
            return 2;
#endif
        }
        return runners.at(command)();
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << prefix << one_line(e.what()) << "\n";
        return 2;
    } catch (const snert::InputError& e) {
        std::cerr << prefix << one_line(e.what()) << "\n";
        return 2;
    } catch (const snert::Cancelled&) {
        std::cerr << prefix << "cancelled\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << prefix << "internal error: " << one_line(e.what()) << "\n";
        return 1;
    }
}
