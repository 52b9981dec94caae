#include "error_report.h"

#include <cstdio>
#include <new>

#include "errors.h"
#include "gl_program.h"  // RenderError
#include "platform_error.h"

namespace corebox {

ErrorReport describeError(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const InputError& e) {
        return {kExitInput, std::string("corebox: error: ") + e.what()};
    } catch (const InstabilityError& e) {
        return {kExitUnstable, std::string("corebox: ") + e.what()};
    } catch (const DeviceError& e) {
        return {kExitDevice, std::string("corebox: device error: ") + e.what()};
    } catch (const PlatformError& e) {
        return {kExitDevice, std::string("corebox: device error: ") + e.what()};
    } catch (const RenderError& e) {
        return {kExitDevice, std::string("corebox: device error: ") + e.what()};
    } catch (const std::bad_alloc& e) {
        return {kExitDevice, std::string("corebox: device error: out of memory (") + e.what() +
                                 "); use fewer particles or a smaller frame size"};
    } catch (const std::exception& e) {
        return {kExitInput, std::string("corebox: internal error: ") + e.what() +
                                " (a bug in corebox: please report it with the command line that caused it)"};
    } catch (...) {
        return {kExitInput, "corebox: internal error: an exception of unknown type (a bug in corebox: please report it)"};
    }
}

int reportError(const std::exception_ptr& error) {
    const ErrorReport report = describeError(error);
    std::fprintf(stderr, "%s\n", report.message.c_str());
    return report.code;
}

int runReportingErrors(const std::function<void()>& body, const std::function<void()>& afterInstability) {
    try {
        body();
        return kExitOk;
    } catch (...) {
        const int code = reportError();
        if (code != kExitUnstable || !afterInstability) return code;
    }
    try {
        afterInstability();
    } catch (...) {
        reportError();
    }
    return kExitUnstable;
}

}  // namespace corebox
