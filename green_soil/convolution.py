"""A causal convolution of force increments with ramp-response kernels,
over a memory of M steps, as green_soil/track.py steps it: the footprints'
displacement and velocity (one memory) and the receivers' velocities
(another, longer one: waves take longer to reach a receiver 64 m away
than the footprints' coupling needs).

Partitioned: the lags below L are summed directly at every step (the
newest increment may still move, see push()); the lags L to M - 1 of L
outputs at once, at the first step of each block of L, by FFT from the
increments before it, which no later step changes. Cost per step about
L N^2 + (M / L) N^2 complex multiply-adds plus N FFTs of length about 2 M
per block, against M N^2 for the direct sum; the kernels' spectra hold M
to 2 M times N^2 complex numbers each.
"""
from __future__ import annotations

import math

import numpy as np


class Convolution:
    """kernels: arrays (M, rows, n) oldest first (index M - 1 - m holds lag
    m), all of the same memory M; block the partition's length L (None:
    about 2 sqrt(M); 1: the direct sum)."""

    def __init__(self, kernels, block=None):
        self.K = kernels
        self.M, _, self.n = kernels[0].shape
        self.block = block_length(self.M) if block is None else block
        if self.block > 1:
            self.spectra = [tail_spectra(K, self.block) for K in kernels]
        self.reset(np.zeros(self.n))

    def reset(self, forces):
        self.buf = np.zeros((2 * self.M, self.n))  # increments, each written twice
        self.pos = 0  # the next increment goes to buf[pos] and buf[pos + M]
        self.f_old = np.array(forces, dtype=float)  # F_(n-M)
        self.f_last = np.array(forces, dtype=float)  # F_n
        self.steps = 0
        self.tails = None

    def push(self, f_start, f_end):
        """One step with the force linear from f_start to f_end: a list of
        each kernel's sum over the last M increments. A start that differs
        from the last end moves the last increment."""
        M = self.M
        if self.steps > 0:
            last = (self.pos - 1) % M
            jump = f_start - self.f_last
            self.buf[last] += jump
            self.buf[last + M] += jump
        else:
            self.f_old = f_start.copy()
        oldest = self.buf[self.pos].copy()
        inc = f_end - f_start
        self.buf[self.pos] = inc
        self.buf[self.pos + M] = inc
        self.pos = (self.pos + 1) % M
        if self.steps >= M:
            self.f_old += oldest
        self.f_last = f_end.copy()
        self.steps += 1
        win = self.buf[self.pos:self.pos + M]  # the last M increments, oldest first
        if self.block <= 1:
            return [np.einsum("mij,mj->i", K, win) for K in self.K]
        L, j = self.block, (self.steps - 1) % self.block
        if j == 0:  # lags >= L of the block's L outputs, from increments now final
            self.tails = [tails(sp, win[:-1], M, L) for sp in self.spectra]
        near = win[M - L:]
        return [np.einsum("mij,mj->i", K[M - L:], near) + t[j]
                for K, t in zip(self.K, self.tails)]

    def save(self):
        tails_ = None if self.tails is None else [t.copy() for t in self.tails]
        return (self.buf.copy(), self.pos, self.f_old.copy(), self.f_last.copy(), self.steps,
                tails_)

    def restore(self, state):
        buf, self.pos, f_old, f_last, self.steps, tails_ = state
        self.buf, self.f_old, self.f_last = buf.copy(), f_old.copy(), f_last.copy()
        self.tails = None if tails_ is None else [t.copy() for t in tails_]


def block_length(M):
    """L about 2 sqrt(M) (the two parts' costs balanced); 1 (direct) for a
    short memory."""
    return 1 if M < 64 else int(2.0 * math.sqrt(M))


def tail_spectra(K, L):
    """The spectra of the kernel's lags L..M-1 (K oldest first, (M, rows, n))."""
    M = K.shape[0]
    nfft = 1 << int(math.ceil(math.log2(2 * M)))
    lagged = np.zeros((nfft,) + K.shape[1:])
    lagged[L:M] = K[::-1][L:M]
    return np.fft.rfft(lagged, axis=0), nfft


def tails(spec, history, M, L):
    """(L, rows): sum over lags p in [L, M) of K_p x_(n+j-p), j < L, from the
    M - 1 increments before step n (history, oldest first)."""
    kf, nfft = spec
    hf = np.fft.rfft(history, nfft, axis=0)
    return np.fft.irfft(np.einsum("fij,fj->fi", kf, hf), nfft, axis=0)[M - 1:M - 1 + L]
