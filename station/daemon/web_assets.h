#pragma once
// The operator's web page (station/daemon/web/), built into the binary by
// cmake/EmbedFiles.cmake: the daemon serves it with nothing installed beside it.
#include <string_view>
#include <vector>

namespace ts::daemon {

struct WebFile {
  std::string_view path;  // "/index.html", "/app.js", ...
  std::string_view body;
};

extern const std::vector<WebFile> kWebFiles;

// The file served at `path` ("/" is /index.html); nullptr when there is none.
const WebFile* FindWebFile(std::string_view path);
// By extension: text/html, text/javascript, text/css (utf-8), image/svg+xml.
const char* WebContentType(std::string_view path);

}  // namespace ts::daemon
