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
    3 R receiver values: the vertical ones, then x, then y)."""

    def __init__(self, layers, footprints, receivers, H, memory, f_max=150.0,
                 disc=greens.Discretisation(), cache_dir=None, workers=0, block=None,
                 horizontal=False):
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
        rec = R.Record(dt=H, duration=max(self.M * H, MIN_RECORD), f_max=f_max)
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
        self.block = _block_length(self.M) if block is None else block
        if self.block > 1:
            self.spectra_ = [_tail_spectra(K, self.block) for K in (self.S, self.V, self.R)]
        self.reset(np.zeros(n))

    def _receiver_kernels(self, layers, rec, how, offsets, points, gather):
        """The receivers' velocity kernels (M, rows, n), oldest first: the
        vertical rows, then the x and the y rows when horizontal (the
        radial displacement's x and y parts, radial.point_means; odd in dx
        and dy respectively, so computed at |dx|, |dy| and signed)."""
        disc, cache_dir, workers = how
        qidx, spec_q, n_rec, n = gather
        iw = 1j * rec.frequencies()[1]
        blocks = [(R.ramp_responses(spec_q * iw[None, :], rec, self.M), None)] if n_rec else []
        if self.horizontal:
            spec_h, _ = R.cached_horizontal(layers, self.fp, points, rec, disc, cache_dir, workers)
            signed = np.array(offsets, dtype=float)
            for c in (0, 1):
                blocks.append((R.ramp_responses(spec_h[c] * iw[None, :], rec, self.M),
                               np.sign(signed[:, c])))
        if not blocks:
            return np.zeros((self.M, 0, n))
        out = [_gather(s, qidx, n_rec, n, sign) for s, sign in blocks]
        return np.ascontiguousarray(np.concatenate(out, axis=1)[::-1])

    def reset(self, forces):
        """The state at rest under `forces` (the static state)."""
        self.buf = np.zeros((2 * self.M, self.n))  # increments, each written twice
        self.pos = 0  # the next increment goes to buf[pos] and buf[pos + M]
        self.f_old = np.array(forces, dtype=float)  # F_(n-M)
        self.f_last = np.array(forces, dtype=float)  # F_n
        self.steps = 0
        self.tails = None
        return self.S_static @ self.f_old

    def _window(self):
        return self.buf[self.pos:self.pos + self.M]  # the last M increments, oldest first

    def step(self, f_start, f_end):
        """Advance one step with the force linear from f_start to f_end;
        returns (u, v, receiver velocities) at its end. A start that differs
        from the last end moves the last increment (the force at that
        instant is f_start)."""
        f_start = np.asarray(f_start, dtype=float)
        f_end = np.asarray(f_end, dtype=float)
        if self.steps > 0:
            last = (self.pos - 1) % self.M
            jump = f_start - self.f_last
            self.buf[last] += jump
            self.buf[last + self.M] += jump
        else:
            self.f_old = f_start.copy()
        oldest = self.buf[self.pos].copy()
        inc = f_end - f_start
        self.buf[self.pos] = inc
        self.buf[self.pos + self.M] = inc
        self.pos = (self.pos + 1) % self.M
        if self.steps >= self.M:
            self.f_old += oldest
        self.f_last = f_end.copy()
        self.steps += 1
        win = self._window()
        if self.block <= 1:
            u, v, r = (np.einsum("mij,mj->i", K, win) for K in (self.S, self.V, self.R))
            return u + self.S_static @ self.f_old, v, r
        L, j = self.block, (self.steps - 1) % self.block
        if j == 0:  # lags >= L of the block's L outputs, from increments now final
            self.tails = [_tails(sp, win[:-1], self.M, L) for sp in self.spectra_]
        near = win[self.M - L:]
        u, v, r = (np.einsum("mij,mj->i", K[self.M - L:], near) + t[j]
                   for K, t in zip((self.S, self.V, self.R), self.tails))
        return u + self.S_static @ self.f_old, v, r

    def save(self):
        tails = None if self.tails is None else [t.copy() for t in self.tails]
        return (self.buf.copy(), self.pos, self.f_old.copy(), self.f_last.copy(), self.steps,
                tails)

    def restore(self, state):
        buf, self.pos, f_old, f_last, self.steps, tails = state
        self.buf, self.f_old, self.f_last = buf.copy(), f_old.copy(), f_last.copy()
        self.tails = None if tails is None else [t.copy() for t in tails]


# Partitioned convolution: the lags below L are summed directly at every
# step (the newest increment may still move, see step()); the lags L to
# M - 1 of L outputs at once, at the first step of each block of L, by FFT
# from the increments before it, which no later step changes. Cost per step
# about L N^2 + (M / L) N^2 complex multiply-adds plus N FFTs of length
# about 2 M per block, against M N^2 for the direct sum; the kernels'
# spectra hold M to 2 M times N^2 complex numbers each.


def _gather(s, idx, rows, n, sign=None):
    """(M, rows, n) from responses s (offsets, M) by the index of each
    (row, footprint) offset, the first half to the footprints, the second
    to their mirrors, each times its sign when given."""
    v = s[idx] if sign is None else s[idx] * sign[:, None]
    h = len(idx) // 2
    return (v[:h] + v[h:]).T.reshape(-1, rows, n)


def _block_length(M):
    """L about 2 sqrt(M) (the two parts' costs balanced); 1 (direct) for a
    short memory."""
    return 1 if M < 64 else int(2.0 * math.sqrt(M))


def _tail_spectra(K, L):
    """The spectra of the kernel's lags L..M-1 (K oldest first, (M, rows, n))."""
    M = K.shape[0]
    nfft = 1 << int(math.ceil(math.log2(2 * M)))
    lagged = np.zeros((nfft,) + K.shape[1:])
    lagged[L:M] = K[::-1][L:M]
    return np.fft.rfft(lagged, axis=0), nfft


def _tails(spec, history, M, L):
    """(L, rows): sum over lags p in [L, M) of K_p x_(n+j-p), j < L, from the
    M - 1 increments before step n (history, oldest first)."""
    kf, nfft = spec
    hf = np.fft.rfft(history, nfft, axis=0)
    return np.fft.irfft(np.einsum("fij,fj->fi", kf, hf), nfft, axis=0)[M - 1:M - 1 + L]
