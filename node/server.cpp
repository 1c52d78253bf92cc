#include "server.hpp"

#include "server_conn.hpp"

#include <algorithm>

namespace railcosim {

NodeServer::NodeServer(NodeOptions options, const Address& listen, ServerLimits limits)
    : options_(std::move(options)), limits_(limits), acceptor_(io_) {
  boost::system::error_code ec;
  const auto ip = asio::ip::make_address(listen.host, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + listen.str() + ": '" + listen.host +
                             "' is not an IP address");
  const tcp::endpoint ep(ip, listen.port);
  acceptor_.open(ep.protocol(), ec);
  if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(ep, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("cannot listen on " + listen.str() + ": " + ec.message());
  worker_ = std::thread([this] { work(); });
}

NodeServer::~NodeServer() {
  stopping_ = true;
  {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    quit_ = true;
  }
  jobs_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void NodeServer::run_on_worker(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    jobs_.push_back(std::move(job));
  }
  jobs_cv_.notify_one();
}

void NodeServer::work() {
  while (true) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(jobs_mutex_);
      jobs_cv_.wait(lock, [this] { return quit_ || !jobs_.empty(); });
      if (jobs_.empty()) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();
  }
}

Address NodeServer::local_address() const {
  const auto ep = acceptor_.local_endpoint();
  return Address{ep.address().to_string(), ep.port()};
}

void NodeServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec != asio::error::operation_aborted) accept();
      return;
    }
    if (active_ && active_->inbox()->waiting()) {
      // A peer link of the session's direct data plane: its worker checks
      // the hello and the secret.
      const std::string from = endpoint_text(socket);
      const int fd = ::dup(socket.native_handle());
      socket.close(ec);
      if (fd >= 0) active_->inbox()->offer(fd, from);
      accept();
      return;
    }
    auto conn = std::make_shared<Conn>(*this, std::move(socket));
    if (active_) {
      logger(options_.role)
          ->warn("refused a connection from {}: busy with the session from {}", conn->peer(),
                 active_->peer());
      conn->refuse_busy();
    } else if (opening_.size() >= kMaxOpenings) {
      logger(options_.role)
          ->warn("refused a connection from {}: {} others are saying hello", conn->peer(),
                 opening_.size());
      conn->refuse_busy();
    } else {
      opening_.push_back(conn);
      conn->start();
    }
    accept();
  });
}

bool NodeServer::opened(Conn* c) {
  const auto it = std::find_if(opening_.begin(), opening_.end(),
                               [c](const std::shared_ptr<Conn>& o) { return o.get() == c; });
  if (it == opening_.end() || active_) return false;
  active_ = *it;
  opening_.erase(it);
  ++sessions_;
  return true;
}

void NodeServer::session_ended(Conn* c) {
  if (active_.get() == c) active_.reset();
  opening_.erase(std::remove_if(opening_.begin(), opening_.end(),
                                [c](const std::shared_ptr<Conn>& o) { return o.get() == c; }),
                 opening_.end());
}

void NodeServer::run(bool handle_signals) {
  asio::signal_set signals(io_);
  if (handle_signals) {
    signals.add(SIGINT);
    signals.add(SIGTERM);
    signals.async_wait([this](boost::system::error_code ec, int sig) {
      if (ec) return;
      logger(options_.role)->info("signal {} received: stopping", sig);
      stop();
    });
  }
  accept();
  io_.run();
}

void NodeServer::stop() {
  stopping_ = true;  // a step in progress gives up at once
  asio::post(io_, [this] {
    boost::system::error_code ec;
    acceptor_.close(ec);
    if (active_) {
      active_->inbox()->cancel();
      active_->inbox()->shut_down_links();
      active_->close();
    }
    for (const auto& c : opening_) c->close();
    io_.stop();
  });
}

}  // namespace railcosim
