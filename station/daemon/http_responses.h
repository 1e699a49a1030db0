#pragma once
// The API's answers: JSON bodies, errors as {"error": "..."}, files streamed from disk.
#include <nlohmann/json.hpp>
#include <string>

#include "core/log.h"  // before httplib: see http_api.h

#include <httplib.h>  // NOLINT(build/include_order)

namespace ts::daemon {

void SendJson(httplib::Response& res, int status, const nlohmann::json& body);
void SendError(httplib::Response& res, int status, const std::string& message);
// Streams `path` (a file the caller checked) in 64 KiB pieces.
void SendFile(httplib::Response& res, const std::string& path, const char* content_type);

}  // namespace ts::daemon
