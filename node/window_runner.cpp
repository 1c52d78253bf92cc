#include "window_runner.hpp"

#include <cmath>
#include <limits>

#include "work_budget.hpp"

namespace railcosim {

using Clock = std::chrono::steady_clock;

WindowRunner::WindowRunner(Subsystem& subsystem, LinksPlan plan,
                           std::vector<std::unique_ptr<FdChannel>> links, double macro_step,
                           CouplingData outputs, long point)
    : sub_(subsystem),
      refresh_(plan.refresh),
      timeout_(plan.timeout),
      macro_step_(macro_step),
      outputs_(std::move(outputs)),
      point_(point) {
  for (std::size_t k = 0; k < links.size(); ++k)
    links_.push_back(Link{std::move(links[k]), plan.links[k], -1, {}, -1, {}});
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
        if (x.kind() != LinkError::Kind::kTimeout) throw;
        if (first && report_) flush(id_, *report_, l.plan.peer);
        if (abandoned_ && *abandoned_ && (*abandoned_)())
          throw LinkError(LinkError::Kind::kClosed,
                          "the master closed the session while this participant waited for " +
                              l.channel->what());
      }
    }
    if (!e.has_peer_data())
      throw LinkError(LinkError::Kind::kProtocol,
                      l.channel->what() + " sent " + body_name(e) + " on its peer link");
    const wire::PeerData& d = e.peer_data();
    if (d.last() && d.point() < end_) {
      end_ = d.point();
      why_ = l.channel->what() + " stops at macro step " + std::to_string(end_);
    }
    if (d.data().interfaces_size() == 0) continue;  // a marker only
    if (static_cast<std::size_t>(d.data().interfaces_size()) != l.plan.interfaces.size())
      throw LinkError(LinkError::Kind::kProtocol,
                      l.channel->what() + " sent " + std::to_string(d.data().interfaces_size()) +
                          " interfaces on a link of " + std::to_string(l.plan.interfaces.size()));
    (d.refresh() ? l.fresh : l.data) = from_wire(d.data());
    (d.refresh() ? l.fresh_have : l.have) = d.point();
  }
  return true;
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
                        " that this participant rejects: " + e.what());
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
  wire::Envelope e;
  e.set_id(id);
  e.mutable_reports()->Swap(&pending_);
  e.mutable_reports()->set_waiting_for(waiting_for);
  report(encode_frame(e));
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
  }
  if (point_ < w.end_step()) send_stop();
  flush(id, report);
  wire::WindowDone done;
  done.set_step(point_);
  if (point_ < w.end_step()) done.set_reason(why_);
  return done;
}

}  // namespace railcosim
