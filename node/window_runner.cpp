#include "window_runner.hpp"

#include <cmath>
#include <limits>

#include "work_budget.hpp"

namespace railcosim {

using Clock = std::chrono::steady_clock;

InputShape input_shape(const wire::Configure& c) {
  InputShape shape;
  for (const auto& w : c.interfaces()) {
    std::array<std::size_t, 3> counts{0, 0, 0};
    for (Quantity q : from_wire(w).receives())
      counts[static_cast<std::size_t>(q)] = static_cast<std::size_t>(w.x_size());
    shape.push_back(counts);
  }
  return shape;
}

WindowRunner::WindowRunner(Participant& participant, LinksPlan plan,
                           std::vector<std::unique_ptr<FdChannel>> links, double macro_step,
                           CouplingData outputs, InputShape shape, long point,
                           std::size_t max_frame_bytes)
    : sub_(participant),
      max_frame_bytes_(max_frame_bytes),
      refresh_(plan.refresh),
      timeout_(plan.timeout),
      macro_step_(macro_step),
      outputs_(std::move(outputs)),
      shape_(std::move(shape)),
      point_(point) {
  // Every link's data starts at the current point.
  for (std::size_t k = 0; k < links.size(); ++k)
    links_.push_back(Link{std::move(links[k]), plan.links[k], point - 1, {}, point - 1, {}});
}

void WindowRunner::send_outputs(const CouplingData& outputs, bool last, bool refresh) {
  for (Link& l : links_) {
    wire::Envelope e;
    auto* d = e.mutable_peer_data();
    d->set_point(point_);
    d->set_last(last);
    d->set_refresh(refresh);
    auto* data = d->mutable_data();
    for (int i : l.plan.interfaces)
      to_wire(outputs[static_cast<std::size_t>(i)], data->add_interfaces());
    l.channel->send(e, timeout_);
  }
  if (!refresh) sent_ = point_;
  sent_last_ = sent_last_ || last;
}

void WindowRunner::send_stop() {
  if (sent_last_) return;
  sent_last_ = true;
  for (Link& l : links_) {
    wire::Envelope e;
    e.mutable_peer_data()->set_point(point_);
    e.mutable_peer_data()->set_last(true);
    try {
      l.channel->send(e, std::chrono::milliseconds(1000));
    } catch (const LinkError&) {
      // That peer is gone already.
    }
  }
}

bool WindowRunner::await(Link& l, long need, bool fresh) {
  while ((fresh ? l.fresh_have : l.have) < need) {
    if (end_ < need) return false;
    // Data that does not come at once: after a moment the master is told
    // whom this participant waits for (with the reports it has), so that it
    // can name the one that hangs; the wait goes on to the link's deadline.
    wire::Envelope e;
    const auto patience = std::chrono::milliseconds(50);
    const auto started = Clock::now();
    for (bool first = true;; first = false) {
      const auto waited =
          std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started);
      if (waited >= timeout_)
        throw LinkError(LinkError::Kind::kTimeout, l.channel->what() + " sent nothing within " +
                                                       std::to_string(timeout_.count()) + " ms");
      try {
        e = l.channel->receive(std::min(patience, timeout_ - waited));
        break;
      } catch (const LinkError& x) {
        // A frame that is not a message, or one over the limit: the sender's.
        if (x.kind() == LinkError::Kind::kProtocol)
          throw LinkError(x.kind(), x.what(), l.plan.peer);
        if (x.kind() != LinkError::Kind::kTimeout) throw;
        if (waited + patience >= timeout_)  // the whole wait, not its last slice
          throw LinkError(LinkError::Kind::kTimeout,
                          l.channel->what() + " sent nothing within " +
                              std::to_string(timeout_.count()) + " ms (the link's " +
                              "deadline), while this participant waited for macro step " +
                              std::to_string(need));
        if (first && report_) flush(id_, *report_, l.plan.peer);
        if (abandoned_ && *abandoned_ && (*abandoned_)())
          throw LinkError(LinkError::Kind::kClosed,
                          "the master closed the session while this participant waited for " +
                              l.channel->what());
      }
    }
    if (!e.has_peer_data())
      throw LinkError(LinkError::Kind::kProtocol,
                      l.channel->what() + " sent " + body_name(e) + " on its peer link" + at(),
                      l.plan.peer);
    take(l, e.peer_data());
  }
  return true;
}

std::string WindowRunner::at() const {
  return " at macro step " + std::to_string(point_) +
         " (t = " + std::to_string(static_cast<double>(point_) * macro_step_) + " s)";
}

void WindowRunner::take(Link& l, const wire::PeerData& d) {
  auto bad = [&](const std::string& what) {
    return LinkError(LinkError::Kind::kProtocol, l.channel->what() + " sent " + what + at(),
                     l.plan.peer);
  };
  const long p = d.point();  // wide enough for any value on the wire
  const bool data = d.data().interfaces_size() > 0;
  // Points go up by one on a link: data at every point, in order; the
  // second sending (refresh) of a point after its first; a stop marker at
  // the last point sent or the next.
  long due = l.have + 1;
  if (!data && d.last()) {
    if (p < l.have || p > l.have + 1)
      throw bad("a stop marker for point " + std::to_string(p) + ", its data being at point " +
                std::to_string(l.have));
  } else if (!data) {
    throw bad("peer data for point " + std::to_string(p) + " with no values and no stop");
  } else if (d.refresh()) {
    if (!l.plan.refreshes)
      throw bad("a second sending (refresh) on a link whose peer sends once per step");
    due = l.fresh_have + 1;
    if (p != due || p > l.have)
      throw bad("a second sending for point " + std::to_string(p) + " where point " +
                std::to_string(due) + " was due");
  } else if (p != due) {
    throw bad("data for point " + std::to_string(p) + " where point " + std::to_string(due) +
              " was due");
  }
  if (d.last() && p < end_) {
    end_ = p;
    why_ = l.channel->what() + " stops at macro step " + std::to_string(end_);
  }
  if (!data) return;  // a marker only
  if (static_cast<std::size_t>(d.data().interfaces_size()) != l.plan.interfaces.size())
    throw bad(std::to_string(d.data().interfaces_size()) + " interfaces on a link of " +
              std::to_string(l.plan.interfaces.size()));
  CouplingData values = from_wire(d.data());
  // Every count is checked here, against the scene's interfaces, so that a
  // wrong one is the sender's fault and not the receiving participant's.
  for (std::size_t e = 0; e < values.size(); ++e) {
    const auto j = static_cast<std::size_t>(l.plan.interfaces[e]);
    const InterfaceData& v = values[e];
    const std::size_t got[3] = {v.displacement.size(), v.velocity.size(), v.force.size()};
    static const char* const kName[3] = {"displacement", "velocity", "force"};
    for (int q = 0; q < 3; ++q)
      if (got[q] != shape_[j][static_cast<std::size_t>(q)])
        throw bad(std::to_string(got[q]) + " " + kName[q] + " values for point " +
                  std::to_string(p) + " on interface " + std::to_string(j) + ", where " +
                  std::to_string(shape_[j][static_cast<std::size_t>(q)]) + " are expected");
  }
  // A peer's last data may hold its divergence (values not finite); it
  // ends the run there.
  if (!d.last())
    for (const InterfaceData& i : values)
      for (const auto* v : {&i.displacement, &i.velocity, &i.force})
        for (double x : *v)
          if (!std::isfinite(x)) throw bad("a non-finite value for point " + std::to_string(p));
  (d.refresh() ? l.fresh : l.data) = std::move(values);
  (d.refresh() ? l.fresh_have : l.have) = p;
}

void WindowRunner::set_inputs(long n, bool fresh) {
  try {
    sub_.set_inputs(n, inputs(fresh));
  } catch (const BadInputError& e) {
    // The data came from a peer: name it (the one with a value that is not
    // finite, else the only one), so that the master blames the sender.
    const Link* from = links_.size() == 1 ? &links_.front() : nullptr;
    for (const Link& l : links_)
      for (const InterfaceData& d : fresh&& l.plan.refreshes ? l.fresh : l.data)
        for (const auto* v : {&d.displacement, &d.velocity, &d.force})
          for (double x : *v)
            if (!std::isfinite(x)) from = &l;
    throw LinkError(LinkError::Kind::kProtocol,
                    (from ? from->channel->what() : std::string("a peer")) +
                        " sent data for macro step " + std::to_string(n) +
                        " that this participant rejects: " + e.what(),
                    from ? from->plan.peer : std::string());
  }
}

CouplingData WindowRunner::inputs(bool fresh) const {
  CouplingData in(outputs_.size());
  for (const Link& l : links_) {
    const CouplingData& d = fresh && l.plan.refreshes ? l.fresh : l.data;
    for (std::size_t e = 0; e < l.plan.interfaces.size(); ++e)
      in[static_cast<std::size_t>(l.plan.interfaces[e])] = d[e];
  }
  return in;
}

void WindowRunner::flush(std::uint64_t id, const std::function<void(const std::string&)>& report,
                         const std::string& waiting_for) {
  if (pending_.reports_size() == 0 && waiting_for.empty()) return;
  // As many reports per frame as the node's frame limit allows: the frame's
  // header, the envelope and a report's own tag and length cost at most this.
  const std::size_t overhead = kFrameHeaderBytes + 32 + waiting_for.size();
  wire::Envelope e;
  e.set_id(id);
  auto* out = e.mutable_reports();
  out->set_waiting_for(waiting_for);
  std::size_t size = overhead;
  for (auto& r : *pending_.mutable_reports()) {
    const std::size_t cost = r.ByteSizeLong() + 6;
    if (overhead + cost > max_frame_bytes_)
      throw ProtocolError(wire::Error::FRAME_TOO_LARGE,
                          "the step report of macro step " + std::to_string(r.step()) + " (" +
                              std::to_string(cost) + " bytes) does not fit in a frame under " +
                              "this node's --max-frame-bytes of " +
                              std::to_string(max_frame_bytes_));
    if (size + cost > max_frame_bytes_) {
      report(encode_frame(e, max_frame_bytes_));
      out->clear_reports();
      size = overhead;
    }
    *out->add_reports() = std::move(r);
    size += cost;
  }
  pending_.clear_reports();
  report(encode_frame(e, max_frame_bytes_));
}

wire::WindowDone WindowRunner::run(const wire::Window& w, std::uint64_t id,
                                   const std::function<void(const std::string&)>& report,
                                   const std::function<bool()>& abandoned) {
  if (w.first_step() != point_)
    throw ProtocolError(wire::Error::OUT_OF_ORDER,
                        "window from macro step " + std::to_string(w.first_step()) +
                            ", but this participant is at " + std::to_string(point_));
  if (w.end_step() <= w.first_step())
    throw ProtocolError(wire::Error::BAD_REQUEST, "a window must hold at least one macro step");
  end_ = w.end_step();
  why_.clear();
  id_ = id;
  report_ = &report;
  abandoned_ = &abandoned;
  const double bound = w.divergence_bound();
  const std::size_t every = w.report_steps() > 0 ? w.report_steps() : 64;
  auto last_flush = Clock::now();
  WorkBudget& budget = current_work_budget();
  try {
    if (sent_ < point_) send_outputs(outputs_, false, false);
    while (point_ < end_) {
      const long n = point_;
      bool go = true;
      for (Link& l : links_) go = go && await(l, n + (l.plan.ahead ? 1 : 0), false);
      if (!go || n >= end_) break;
      set_inputs(n, false);
      if (refresh_) send_outputs(sub_.outputs(), false, true);
      bool again = false;
      for (Link& l : links_)
        if (l.plan.refreshes) {
          if (!await(l, n, true)) go = false;
          again = true;
        }
      if (!go) break;
      if (again) set_inputs(n, true);
      if (budget.limit.count() > 0) budget.deadline = Clock::now() + budget.limit;
      StepResult r;
      try {
        r = sub_.step(n);
      } catch (const StepFailure&) {
        send_stop();
        flush(id, report);
        throw;
      }
      point_ = n + 1;
      outputs_ = r.outputs;
      const bool diverged = bound > 0 && (!r.finite || r.max_abs_displacement > bound);
      if (diverged) {
        end_ = point_;
        why_ = "diverged at macro step " + std::to_string(point_);
      }
      send_outputs(outputs_, diverged, false);
      *pending_.add_reports() = to_wire(r, point_, static_cast<double>(point_) * macro_step_);
      const auto now = Clock::now();
      if (static_cast<std::size_t>(pending_.reports_size()) >= every ||
          now - last_flush >= std::chrono::milliseconds(20)) {
        flush(id, report);
        last_flush = now;
      }
    }
  } catch (const LinkError&) {
    send_stop();
    flush(id, report);
    throw;
  } catch (const ProtocolError&) {
    send_stop();
    throw;
  }
  if (point_ < w.end_step()) send_stop();
  flush(id, report);
  wire::WindowDone done;
  done.set_step(point_);
  if (point_ < w.end_step()) done.set_reason(why_);
  return done;
}

}  // namespace railcosim
