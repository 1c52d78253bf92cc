"""What a solver author writes: a subclass of `Participant`, physics only.

The SDK calls, in this order, once per session:

    configure(config, interfaces)          -> None
    statics(inputs)                        -> outputs   (any number of times)
    initialize(inputs)                     -> outputs   (default: statics)
    advance(t, H, inputs)                  -> outputs   (once per macro step,
                                                         repeated after restore
                                                         under implicit coupling)
    save() -> list of floats; restore(state)             (around repeated steps)
    results()                              -> list of arrays (after the last step)

`inputs` is a list with one `Inputs` per interface, in the configured order;
each quantity the interface receives is a `Waveform` over the macro step
(held or ramped), or with substep waveforms a `Sampled` one (waveforms.py);
both have start, end, at(t) and rate().
`outputs` is a list with one dict per interface, {"displacement": array,
"velocity": array} or {"force": array}: the quantities the interface sends,
one value per coupling point, at the end of the call (t + H for advance).

Everything else (frames, authentication, order of messages, the relayed and
the direct data plane, implicit iterations, the step counter, the held
inputs, checking shapes and finiteness) is the SDK's.
"""

import numpy as np

QUANTITIES = ("displacement", "velocity", "force")


class StepFailed(Exception):
    """Raise from advance() when the integrator gives up on a macro step: the
    master records the run as diverged (a result, not a failure)."""


class BadInterface(Exception):
    """Raise from configure() when an interface cannot be honoured (a cut the
    model has no side of, a wrong number of points, quantities it cannot
    receive or send). Say which interface and why."""


class BadRequest(Exception):
    """Raise when a request cannot be served (e.g. a Configure asking for
    adaptive micro steps from a solver with fixed ones)."""


class Footprint:
    """The area one coupling point stands for (read-only): a rectangle
    centred on (x, y), `length` m along the track (x) and `width` m across
    it (y), at depth z below the surface of the cut (0: on it). x is along
    the track as Interface.x, y across from the track axis. At the ss cut:
    one rail's share of a sleeper bay (x the sleeper, length the spacing,
    width half the sleeper's length, y = width/2; the track is symmetric
    about its axis, so the mirror image at -y carries the same force).
    `area` is length * width."""

    __slots__ = ("x", "y", "z", "length", "width")

    def __init__(self, x, y, z, length, width):
        self.x, self.y, self.z, self.length, self.width = x, y, z, length, width

    @property
    def area(self):
        return self.length * self.width

    def __repr__(self):
        return "Footprint(x=%g, y=%g, z=%g, %g x %g m)" % (self.x, self.y, self.z, self.length,
                                                         self.width)


class Interface:
    """One side of one cut, as this participant sees it (read-only).

    cut: "wr", "rs" or "ss"; peer: the participant on the other side;
    upper: True when this side is above the element; x: coupling point
    positions at t = 0 (numpy array, m); n: the number of points; speed:
    m/s the points move at; receives, sends: tuples of quantity names
    ("displacement", "velocity", "force"); stiffness (N/m), damping (N s/m),
    hertz_constant (N/m^1.5): the element at the cut, per point;
    footprints: at the ss cut one `Footprint` per point (in the order of x),
    the area of the soil's surface the point stands for; empty elsewhere.
    """

    def __init__(self, wire):
        self.cut = wire.cut
        self.peer = wire.peer
        self.upper = wire.upper
        self.x = np.array(wire.x, dtype=float)
        self.n = len(self.x)
        self.speed = wire.speed
        self.receives = tuple(QUANTITIES[q - 1] for q in wire.receives)
        self.sends = tuple(QUANTITIES[q - 1] for q in wire.sends)
        self.stiffness = wire.stiffness
        self.damping = wire.damping
        self.hertz_constant = wire.hertz_constant
        self.footprints = tuple(Footprint(f.x, f.y, f.z, f.length, f.width)
                                for f in wire.footprints)

    def __repr__(self):
        return "Interface(%s %s side, %d points, receives %s, sends %s)" % (
            self.cut, "upper" if self.upper else "lower", self.n,
            "/".join(self.receives), "/".join(self.sends))


class Waveform:
    """An input quantity over the macro step [t0, t0 + H]: `start` at t0,
    `end` at t0 + H (numpy arrays, one value per coupling point). Held
    inputs have end is start; ramped ones (linear, extrapolated inputs,
    implicit coupling) are linear in between. `at(t)` evaluates it."""

    __slots__ = ("start", "end", "t0", "H", "held")

    def __init__(self, start, end, t0, H):
        self.start, self.t0, self.H = start, t0, H
        self.held = end is None
        self.end = start if end is None else end

    def at(self, t):
        if self.held:
            return self.start
        return self.start + (self.end - self.start) * ((t - self.t0) / self.H)

    def rate(self):
        """d/dt over the step (zeros when held)."""
        if self.held:
            return np.zeros_like(self.start)
        return (self.end - self.start) / self.H


class Inputs:
    """The inputs of one interface over a macro step: one `Waveform` per
    received quantity, as attributes (`displacement`, `velocity`, `force`);
    quantities the interface does not receive are None."""

    __slots__ = QUANTITIES

    def __init__(self, displacement=None, velocity=None, force=None):
        self.displacement, self.velocity, self.force = displacement, velocity, force


class Run:
    """The run's settings from Configure (read-only): macro_step (H, s),
    end_time (s), tolerance (m), micro_steps (> 0: that many per macro step;
    0: adapt), max_micro_steps (0: own limit), carry_acceleration (the
    restart convention: False = consistent)."""

    def __init__(self, c):
        self.macro_step = c.macro_step
        self.end_time = c.end_time
        self.tolerance = c.tolerance
        self.micro_steps = c.micro_steps
        self.max_micro_steps = c.max_micro_steps
        self.carry_acceleration = c.carry_acceleration


class Participant:
    """Base class of a participant. Subclass it and override the physics.

    Class attributes to set:
      name:    the participant served ("soil"); the master's hello must ask
               for it, and its configuration table defaults to [name].
      history: the names of the values history() returns after every step.
      results_fields: the names of the arrays results() returns.
      takes_waveforms: True when advance() evaluates its inputs with at(t)
               at its own micro steps and calls record() after each of
               them: the participant then takes substep waveforms
               (--inputs waveform0..3), whose quantities are `Sampled`.

    Attributes the SDK sets before configure(): self.run (a `Run`).
    Attribute the author keeps up to date: self.micro_steps (int, the micro
    steps taken in the whole run, reported with the results). A participant
    whose statics() may take long advances self.static_iterations (int, any
    count of its own that grows while statics() works: solver iterations,
    say) as it goes: the SDK sends it in progress frames, and the master
    then waits past its reply limit.
    """

    name = "participant"
    history = ()
    results_fields = ()
    takes_waveforms = False
    micro_steps = 0
    static_iterations = 0
    run = None
    _recorder = None  # the SDK's, while the master asks for samples

    def configure(self, config, interfaces):
        """config: this participant's own table (a dict, from --config);
        interfaces: a list of `Interface`. Build the model; raise
        BadInterface / BadRequest when it cannot serve them. The same
        instance serves one session after another: start afresh here
        (self.micro_steps = 0 included)."""
        raise NotImplementedError

    def check(self, config, interfaces):
        """What `master run --check` asks of a participant the master starts
        itself: raise BadInterface / BadRequest for what configure() would
        refuse, without building anything (the sizes a configuration implies
        included). Default: nothing is checked."""

    def statics(self, inputs):
        """The participant's own static equilibrium with inputs held
        (waveforms with end == start), velocities zero; returns outputs."""
        raise NotImplementedError

    def initialize(self, inputs):
        """Start at t = 0 from the static equilibrium for these inputs."""
        return self.statics(inputs)

    def advance(self, t, H, inputs):
        """Advance from t to t + H with these input waveforms; returns the
        outputs at t + H. May raise StepFailed."""
        raise NotImplementedError

    def outputs(self, inputs):
        """The outputs of the current state with these inputs held (asked
        for a force resolved with fresh inputs). Default: None, meaning the
        outputs last returned (right for any side that sends no force)."""
        return None

    def save(self):
        """Everything needed to go on from here, as a flat list/array of
        floats (the SDK adds its own step counter and held inputs)."""
        raise NotImplementedError

    def restore(self, state):
        """Return bit for bit to a state save() returned (a numpy array)."""
        raise NotImplementedError

    @property
    def recording(self):
        """True while the master asks for the outputs at every micro step."""
        return self._recorder is not None

    def record(self, t, outputs):
        """With takes_waveforms: the outputs (as advance() returns them) at
        time t inside the step, called after each micro step; the SDK adds
        the step's start and, when no sample is at its end, the outputs
        advance() returns. Does nothing unless `recording`."""
        if self._recorder is not None:
            self._recorder.add(t, outputs)

    def history_values(self):
        """One float per declared history channel, for the last state."""
        return ()

    def max_abs_displacement(self):
        """The largest |displacement| over the participant's degrees of
        freedom. Default: over the displacements of its last outputs."""
        return None

    def results(self):
        """One array per declared result field, at the current time."""
        return ()
