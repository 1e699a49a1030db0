#include "station/daemon/web_assets.h"

namespace ts::daemon {

const WebFile* FindWebFile(std::string_view path) {
  if (path == "/") path = "/index.html";
  for (const WebFile& f : kWebFiles)
    if (f.path == path) return &f;
  return nullptr;
}

const char* WebContentType(std::string_view path) {
  auto ends = [&](std::string_view ext) {
    return path.size() >= ext.size() && path.substr(path.size() - ext.size()) == ext;
  };
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".svg")) return "image/svg+xml";
  return "text/html; charset=utf-8";
}

}  // namespace ts::daemon
