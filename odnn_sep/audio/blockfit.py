"""Pass 2 of :func:`denoise`: per-block fits, fixed-line smoothing across blocks, overlap-add.

Each 50 %-overlapping block is fitted by weighted least squares on the tracked harmonic basis
plus the fixed lines (tones, further combs) (fit.py); the fitted hum is windowed by sin^2 (the
windows sum to one, so blocks join without clicks), subtracted and written progressively.

Fixed lines are steady by nature (a second device, another sample clock), and their per-block
amplitudes carry the noise of one block: subtracting them as fitted cuts a notch into the content
under each line as wide as a block allows. So their complex amplitudes are pooled over the
neighbouring blocks (up to ``smooth_blocks`` on each side) with a positive-part James-Stein
weight: the pooled mean where the scatter between blocks is what the local noise floor predicts,
the block's own value where the line really changes. Output is delayed by that many blocks
(memory: a few blocks). The tracked comb is not pooled: its per-block phase reference follows
the track, and its amplitude is free to follow the hum from block to block.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import fit as _fit
from odnn_sep.audio import fullblock as _fullblock

STEADY_SCATTER = 2.0   # scatter over the noise prediction below which a line counts as steady (~1 % test)


def fit_pass(source, sink, *, hop: int, trk, ks, fixed_lines, names, solver: str, random_state, gram_step: int,
             fixed_psd=None, main_psd=None, smooth_blocks: int = 4, tick=None):
    """Fit every block, subtract, write through ``sink(piece, removed)`` (the sink writes
    ``piece - removed``; ``piece`` is what ``source.read`` returned for those samples, so an
    in-memory source's own array can take the result in place).

    ``fixed_psd`` (fixed lines, C), ``main_psd`` (harmonics, C): local noise floor PSD at each line
    (per Hz, one-sided), for the pooling weights; None disables pooling of those lines.
    Returns ``(amps, phs, valid, overall)``: (blocks, C, lines) peak amplitude and phase, which
    blocks are full length, and (C, lines) whole-input amplitudes of steady lines (NaN where a
    line is not steady or not pooled; None without pooling).
    """
    sr, N, C = source.sr, source.frames, source.channels
    nb = (N - 1) // hop + 2
    L = 2 * hop
    pm = 2 * len(ks)
    nfix = sum(len(kk) for _, kk in _fit._as_combs(fixed_lines))
    nl = len(ks) + nfix
    amps = np.zeros((nb, C, nl))
    phs = np.zeros((nb, C, nl))
    valid = np.zeros(nb, bool)
    col_names = [f"{nm}_{cs}" for nm in names for cs in ("cos", "sin")]
    w_full = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    w32_full = w_full.astype(np.float32)
    fitter = _fullblock.FullBlockFitter(L, sr, ks, fixed_lines, w_full, gram_step) if nl else None
    if fitter is not None:
        fitter.phase = getattr(trk, "phase", None)
    pool_fixed = fixed_psd is not None and nfix > 0
    pool_main = main_psd is not None and len(ks) > 0
    M = smooth_blocks if (pool_fixed or pool_main) else 0
    psd = np.vstack(([main_psd] if pool_main else []) + ([fixed_psd] if pool_fixed else [])) if M else None
    pooled_rows = np.r_[np.arange(len(ks)) if pool_main else [], len(ks) + np.arange(nfix) if pool_fixed else []]
    pooled_rows = pooled_rows.astype(int)
    Phi = _block_phase(trk, hop, sr) if pool_main else None
    kk = np.asarray(ks, float)
    basis_cache, sub_cache = {"min_n": L}, {"min_n": L}
    zs, vs = [], []
    prev_piece = np.zeros((0, C))
    prev_tail = np.zeros((C, 0), np.float32)
    for b in range(nb):
        piece = source.read(b * hop, hop)
        s0 = (b - 1) * hop
        parts = [p for p in (prev_piece, piece) if p.shape[0]]
        i0 = max(s0, 0)
        n = prev_piece.shape[0] + piece.shape[0]
        hum = None                                                              # (C, n) float32
        zq = None
        if n and nl:
            theta = Fm = None
            if solver == "exact":
                # blocks cut by the signal's ends too: fitted under a Hann over their visible part
                theta = fitter.fit(i0, b * hop, trk.f0[b], trk.rate[b], trk.curv[b], parts, n=n)
            w = w_full if n == L else np.sin(np.pi * (np.arange(i0, i0 + n) - s0 + 0.5) / L) ** 2
            if theta is None:
                # fit weights: the block's window, or a Hann over the visible part of a block cut
                # by the signal's start/end (a one-sided window would leak the content onto the lines)
                w_fit = fitter.window(n)[0]
                blk = np.vstack(parts) if len(parts) > 1 else parts[0]
                theta, Fm = _fit_generic(i0, n, b * hop, sr, trk, b, ks, fixed_lines, blk, w_fit, solver, gram_step,
                                         basis_cache, sub_cache, col_names, random_state)
            theta = theta[: 2 * nl]
            valid[b] = n == L
            # complex amplitudes a - i b: tracked lines in the block's phase reference, fixed
            # lines in absolute time
            z = theta[0::2] - 1j * theta[1::2]                                  # (nl, C)
            if M:
                zq = z[pooled_rows].copy()
                if pool_main:
                    # tracked lines are pooled in a common phase reference: the track's phase
                    # at each block centre
                    zq[: len(ks)] *= np.exp(-1j * kk * Phi[b])[:, None]
                zs.append(zq)
                # E|z - z0|^2 = 3 S sr / n for a sin^2-weighted fit on noise of PSD S
                vs.append(3.0 * np.maximum(psd, 1e-300) * sr / max(n, 1))
                zp = _pooled(zs, vs, b, M)
                if pool_main:
                    zp[: len(ks)] *= np.exp(1j * kk * Phi[b])[:, None]
                z[pooled_rows] = zp
            amps[b] = np.abs(z).T
            phs[b] = np.angle(z).T
            # unwindowed hum of the block (tracked comb + fixed lines), then one window multiply
            hum = fitter.block_hum(i0, n, z, tracked=Fm is None, slot=b % 2)
            if pm and Fm is not None:
                th = np.empty((C, pm), Fm.dtype)
                th[:, 0::2], th[:, 1::2] = z[: len(ks)].real.T, -z[: len(ks)].imag.T
                hum += np.dot(th, Fm.T)
            hum *= w32_full if n == L else w.astype(np.float32)
        if M and zq is None:
            zs.append(None)
            vs.append(None)
        npv = prev_piece.shape[0]
        if npv:
            removed = (prev_tail + hum[:, :npv] if hum is not None else prev_tail).T
            sink(prev_piece, removed)
        prev_tail = hum[:, npv:] if hum is not None else np.zeros((C, n - npv), np.float32)
        prev_piece = piece
        if tick is not None:
            tick(piece.shape[0])
    return amps, phs, valid, _overall(zs, vs, valid, pooled_rows, nl, C) if M else None


def _overall(zs, vs, valid, rows, nl: int, C: int):
    """One amplitude per line and channel for the whole input: the modulus of the precision-weighted
    mean of the full blocks' complex amplitudes (common phase reference) where the lines are
    steady (scatter between blocks within twice what the floor predicts), NaN elsewhere (the
    caller then reports the median over blocks)."""
    idx = [j for j in range(len(zs)) if zs[j] is not None and valid[j]]
    out = np.full((C, nl), np.nan)
    if len(idx) < 3:
        return out
    # blocks overlap by half: neighbours share a sixth of their noise, so the scatter about the
    # mean is compared with (n - 1) independent-block units
    zbar, r = _mean_scatter(zs, vs, idx)
    steady = r <= STEADY_SCATTER
    out[:, rows] = np.where(steady, np.abs(zbar), np.nan).T
    return out


def _mean_scatter(zs, vs, idx):
    """Precision-weighted mean of the complex amplitudes ``zs[j]`` (lines, C) over blocks ``idx``
    (noise variances ``vs[j]``), and the scatter about it over what the noise predicts (~1 for a
    steady line)."""
    Z = np.stack([zs[j] for j in idx])              # (nw, lines, C)
    W = 1.0 / np.stack([vs[j] for j in idx])
    zbar = (W * Z).sum(axis=0) / W.sum(axis=0)
    r = (W * np.abs(Z - zbar) ** 2).sum(axis=0) / (len(idx) - 1)
    return zbar, r


def _block_phase(trk, hop: int, sr: int) -> np.ndarray:
    """Phase of the tracked fundamental at each block centre (rad, from the first centre): the
    integral of the track between centres by the Hermite (corrected trapezoid) rule. The blocks'
    own cubic terms are left out: they come from second differences of the track and are the
    noisiest part of it."""
    ph = getattr(trk, "phase", None)
    if ph is not None:
        # the refined phase itself: f_ref t + psi(t) at the block centres, from the first one
        c = np.arange(len(trk.f0)) * hop
        cyc = c * (ph.f_ref / ph.sr) + ph.offset_cycles(c.astype(float))
        return 2 * np.pi * np.mod(cyc - cyc[0], 1.0)
    h = hop / sr
    f, r = trk.f0, trk.rate
    cyc = h * (f[:-1] + f[1:]) / 2 + h ** 2 * (r[:-1] - r[1:]) / 12
    step = 2 * np.pi * np.mod(cyc, 1.0)
    return np.concatenate([[0.0], np.cumsum(step)])


def _pooled(zs, vs, f: int, M: int) -> np.ndarray:
    """Positive-part James-Stein pooling of block ``f``'s amplitudes towards the precision-weighted
    mean of blocks ``f - M .. f`` (causal: the output is not delayed)."""
    idx = [j for j in range(f - M, f + 1) if 0 <= j < len(zs) and zs[j] is not None]
    z_f = zs[f]
    if len(idx) < 3:
        return z_f.copy()
    zbar, r = _mean_scatter(zs, vs, idx)
    lam = np.clip(1.0 - 1.0 / np.maximum(r, 1e-12), 0.0, 1.0)
    return zbar + lam * (z_f - zbar)


def _fit_generic(i0, n, centre, sr, trk, b, ks, fixed_lines, blk, w_fit, solver, gram_step, basis_cache,
                 sub_cache, col_names, random_state):
    """One block through the general path (edge blocks, the network solver, ill-conditioned blocks):
    ``(theta (p, C), tracked-comb columns (n, 2K))``; fixed lines in absolute time."""
    # float32 basis for the exact solver: its values come from float32 sines anyway
    # (fit._unit), and the products run at twice the speed (solve_block checks conditioning)
    ph = getattr(trk, "phase", None)
    F = _fit.block_basis(i0, n, centre, sr, trk.f0[b], trk.rate[b], trk.curv[b], ks, fixed_lines,
                         cache=basis_cache, dtype=np.float32 if solver == "exact" else np.float64, phase=ph)
    if solver == "exact":
        F_sub = None
        if _fit.sub_gram(n, F.shape[1], gram_step):
            F_sub = _fit.block_basis(i0, n, centre, sr, trk.f0[b], trk.rate[b], trk.curv[b], ks,
                                     fixed_lines, cache=sub_cache, step=gram_step, dtype=np.float32, phase=ph)
        theta = _fit.solve_block(F, blk, w_fit, gram_step=gram_step, F_sub=F_sub)
    else:
        theta = _fit.solve_block_network(F, blk, w_fit, col_names + ["offset", "trend"],
                                         random_state=random_state)
    return theta, F[:, : 2 * len(ks)]
