#include "web_cmd.hpp"

#include <atomic>
#include <chrono>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "leafdig/db/server_url.hpp"
#include "signals.hpp"

namespace leafdig::cli::web {

int serve(const WebOptions& options, const std::string& listen) {
  const std::size_t colon = listen.rfind(':');
  const std::string host = colon == std::string::npos ? std::string() : listen.substr(0, colon);
  const std::string portText = colon == std::string::npos ? std::string() : listen.substr(colon + 1);
  if (host.empty() || portText.empty() || portText.size() > 5 ||
      portText.find_first_not_of("0123456789") != std::string::npos || std::stoi(portText) > 65535)
    throw std::invalid_argument("--listen '" + listen +
                                "' is not HOST:PORT (e.g. 127.0.0.1:8080; port 0: any free one)");
  installSignalHandlers();
  WebApp app(options);
  HttpServer http([&app](const HttpRequest& request) { return app.handle(request); });
  const int port = http.bind(host, std::stoi(portText));
  std::cout << "leafdig web review on http://" << host << ":" << port << "/ for the lab server "
            << db::redactUrl(options.serverUrl) << " (Ctrl-C stops it)" << std::endl;
  std::atomic<bool> ended{false};
  std::thread server([&http, &ended] {
    http.run();
    ended = true;
  });
  while (!interrupted() && !ended) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  http.stop();
  server.join();
  std::cout << "leafdig web review stopped" << std::endl;
  return 0;
}

}  // namespace leafdig::cli::web
