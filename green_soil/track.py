"""The soil under a track as causal convolutions: the footprints'
displacements and velocities, and the receivers' vertical velocities,
from the history of the footprint forces.

The forces are linear within each step of length H (their values at the
steps' ends, F_n, joined by straight lines). The response to such a force
is a sum of the responses to its increments dF_n = F_n - F_(n-1), each a
unit force ramped over one step and held: the ramp response s_m (at the
m-th step's end after the ramp began; s_0 the instantaneous part). So

    u_n = sum_(m < M) S_m dF_(n-m) + S_static F_(n-M),

the memory truncated at M steps and the rest taken as the last ramp
response, S_static = S_(M-1), also the soil's static flexibility (so the
static state is the dynamics' state at rest). On an elastic ground the
ramp responses settle to the elastic static flexibility (to 0.4 % at
f_max = 200 Hz, 2 % at 100 Hz on a footprint's own); with the hysteretic
loss they creep (spectral.py), and `settled` says by how much at the
memory's end. The ramp
responses are the cumulative sums of the hat responses of responses.py
(one per footprint offset: on a straight track with a constant spacing
one per distance and rail); the matrices S_m[i, j] are gathered from them.
The track is one rail's model, as the FE soil's half block: each
footprint's mirror across the track axis (y -> -y) carries the same force.
"""
from __future__ import annotations

import math

import numpy as np

from . import greens, responses as R
from .convolution import Convolution

MIN_RECORD = 0.5  # s: the Green's functions' record at least (their frequency step 1/(2 T))


def _unique(offsets):
    """(unique |dx|, |dy| offsets, index of each given offset)."""
    keys, index, out = {}, [], []
    for dx, dy in offsets:
        key = (round(abs(dx), 9), round(abs(dy), 9))
        if key not in keys:
            keys[key] = len(out)
            out.append(key)
        index.append(keys[key])
    return out, np.array(index, dtype=np.int64)


def kelvin_ramp(k, c, H, t):
    """Displacement and velocity at times t of a spring k and dashpot c in
    parallel under a force ramped from 0 to 1 over [0, H] and held."""
    tau = c / k
    ramp = t <= H
    tr = np.minimum(t, H)
    u_r = (tr / H - tau / H * (1.0 - np.exp(-tr / tau))) / k
    v_r = (1.0 - np.exp(-tr / tau)) / (k * H)
    decay = np.exp(-np.maximum(t - H, 0.0) / tau)
    u_h = (1.0 - tau / H * (1.0 - math.exp(-H / tau))) / k
    u = np.where(ramp, u_r, 1.0 / k + (u_h - 1.0 / k) * decay)
    v = np.where(ramp, v_r, -(u_h - 1.0 / k) / tau * decay)
    return u, v


class TrackSoil:
    """footprints: (x, y, along, across) per coupling point (equal
    rectangles); receivers: (x, y) surface points; H the step; memory the
    responses' length (s; at most the run's); workers the processes that
    compute the Green's functions (0: the usable cores); block the
    partition's length L (None: about 2 sqrt(M); 1: the direct sum);
    horizontal: the receivers' x and y velocities too (step() then returns
    3 R receiver values: the vertical ones, then x, then y);
    receiver_memory the receivers' responses' length (s; None: memory)."""

    def __init__(self, layers, footprints, receivers, H, memory, f_max=150.0,
                 disc=greens.Discretisation(), cache_dir=None, workers=0, block=None,
                 horizontal=False, receiver_memory=None):
        sizes = {(round(f[2], 9), round(f[3], 9)) for f in footprints}
        if len(sizes) != 1:
            raise ValueError("the footprints differ in size (%s); this soil needs equal ones"
                             % sorted(sizes))
        self.fp = R.Footprint(*sizes.pop())
        x = np.array([f[0] for f in footprints], dtype=float)
        y = np.array([f[1] for f in footprints], dtype=float)
        n = len(x)
        pair_off = ([(x[j] - x[i], y[j] - y[i]) for i in range(n) for j in range(n)]
                    + [(x[j] - x[i], -y[j] - y[i]) for i in range(n) for j in range(n)])
        pairs, pidx = _unique(pair_off)
        rx = [(rx_ - x[j], ry - y[j]) for rx_, ry in receivers for j in range(n)]
        rx += [(rx_ - x[j], ry + y[j]) for rx_, ry in receivers for j in range(n)]
        points, qidx = _unique(rx) if rx else ([], np.zeros(0, np.int64))
        self.M = max(1, int(math.ceil(memory / H - 1e-9)))
        r_memory = memory if receiver_memory is None else receiver_memory
        self.M_receivers = max(1, int(math.ceil(r_memory / H - 1e-9)))
        longest = max(self.M, self.M_receivers)
        rec = R.Record(dt=H, duration=max(longest * H, MIN_RECORD), f_max=f_max)
        spec_p, spec_q, self.cache_hit = R.cached_spectra(layers, self.fp, pairs, points, rec,
                                                          disc, cache_dir, workers)
        static, _ = R.spectra(layers, self.fp, pairs, [], [0.0], disc)
        _, w = rec.frequencies()
        # The footprint's own response has a dashpot's tail at high
        # frequency, 1/(i w C): taken out as a spring and dashpot, whose ramp
        # response is exact, before the spectrum is cut at f_max.
        self.own = [i for i, (dx, dy) in enumerate(pairs) if dx == 0.0 and dy == 0.0]
        top = layers[0]
        self.dashpot = top.density * top.p_speed * self.fp.along * self.fp.across
        spring = 1.0 / static[self.own, 0].real
        spec_p = spec_p.copy()
        spec_p[self.own] -= 1.0 / (spring[:, None] + 1j * w[None, :] * self.dashpot)
        s_u, s_v = (R.ramp_responses(s, rec, self.M) for s in (spec_p, spec_p * (1j * w)[None, :]))
        t = H * np.arange(1, self.M + 1)
        for i, k in zip(self.own, spring):
            du, dv = kelvin_ramp(k, self.dashpot, H, t)
            s_u[i] += du
            s_v[i] += dv
        half = n * n
        # Stored oldest first (index M - 1 - m), so that a window of the
        # force history in time order multiplies them directly.
        self.S = np.ascontiguousarray(_gather(s_u, pidx, n, n)[::-1])
        self.V = np.ascontiguousarray(_gather(s_v, pidx, n, n)[::-1])
        self.horizontal = bool(horizontal and receivers)
        self.R = self._receiver_kernels(layers, rec, (disc, cache_dir, workers), rx, points,
                                        (qidx, spec_q, len(receivers), n))
        # The elastic static flexibility, and how far the responses are from
        # it at the memory's end (the hysteretic loss creeps, see spectral.py).
        self.elastic_static = (static[pidx[:half], 0] + static[pidx[half:], 0]).real.reshape(n, n)
        self.S_static = self.S[0].copy()
        self.settled = float(np.max(np.abs(self.S_static - self.elastic_static))
                             / np.abs(self.elastic_static).max())
        self.n, self.n_receivers = n, len(receivers)
        self.coupling = Convolution([self.S, self.V], block)
        self.receivers = Convolution([self.R], block) if self.R.shape[1] else None
        self.reset(np.zeros(n))

    def _receiver_kernels(self, layers, rec, how, offsets, points, gather):
        """The receivers' velocity kernels (M, rows, n), oldest first: the
        vertical rows, then the x and the y rows when horizontal (the
        radial displacement's x and y parts, radial.point_means; odd in dx
        and dy respectively, so computed at |dx|, |dy| and signed)."""
        disc, cache_dir, workers = how
        qidx, spec_q, n_rec, n = gather
        iw = 1j * rec.frequencies()[1]
        M = self.M_receivers
        blocks = [(R.ramp_responses(spec_q * iw[None, :], rec, M), None)] if n_rec else []
        if self.horizontal:
            spec_h, _ = R.cached_horizontal(layers, self.fp, points, rec, disc, cache_dir, workers)
            signed = np.array(offsets, dtype=float)
            for c in (0, 1):
                blocks.append((R.ramp_responses(spec_h[c] * iw[None, :], rec, M),
                               np.sign(signed[:, c])))
        if not blocks:
            return np.zeros((M, 0, n))
        out = [_gather(s, qidx, n_rec, n, sign) for s, sign in blocks]
        return np.ascontiguousarray(np.concatenate(out, axis=1)[::-1])

    def reset(self, forces):
        """The state at rest under `forces` (the static state)."""
        forces = np.array(forces, dtype=float)
        self.coupling.reset(forces)
        if self.receivers is not None:
            self.receivers.reset(forces)
        return self.S_static @ self.coupling.f_old

    def step(self, f_start, f_end):
        """Advance one step with the force linear from f_start to f_end;
        returns (u, v, receiver velocities) at its end. A start that differs
        from the last end moves the last increment (the force at that
        instant is f_start)."""
        f_start = np.asarray(f_start, dtype=float)
        f_end = np.asarray(f_end, dtype=float)
        u, v = self.coupling.push(f_start, f_end)
        r = (self.receivers.push(f_start, f_end)[0] if self.receivers is not None
             else np.zeros(0))
        return u + self.S_static @ self.coupling.f_old, v, r

    def save(self):
        return (self.coupling.save(),
                None if self.receivers is None else self.receivers.save())

    def restore(self, state):
        self.coupling.restore(state[0])
        if self.receivers is not None:
            self.receivers.restore(state[1])


def _gather(s, idx, rows, n, sign=None):
    """(M, rows, n) from responses s (offsets, M) by the index of each
    (row, footprint) offset, the first half to the footprints, the second
    to their mirrors, each times its sign when given."""
    v = s[idx] if sign is None else s[idx] * sign[:, None]
    h = len(idx) // 2
    return (v[:h] + v[h:]).T.reshape(-1, rows, n)
