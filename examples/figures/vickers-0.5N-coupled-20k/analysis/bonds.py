#!/usr/bin/python3
"""Per-bond axial stress and slip from a vitrum checkpoint (state.h5; needs h5py, numpy). Issue 7, 0.5 N zone study.
sigma_c = -E (eps - eps_r), eps = (l - l0)/l0 (kernels/beam.hpp: N = E S (l - l0)/l0, densification: N = E S (eps - eps_r)).
Positions of bonds: reference (initial) midpoints."""
import h5py, numpy as np, sys, csv, bisect, os, tomllib

def frame(path):
    """(x, y) of the tool's axis and z of the sample's top face, from the resolved_scene.toml beside the
    checkpoint: (0, 0, 0) for the hemisphere scenes, (15, 15, 30) um for the 30 um box of
    examples/vickers-0.1N-box.toml."""
    scene = os.path.join(os.path.dirname(os.path.abspath(path)), 'resolved_scene.toml')
    if not os.path.exists(scene):
        return 0.0, 0.0, 0.0
    s = tomllib.load(open(scene, 'rb'))
    ind = s.get('indenter', {}); smp = s.get('sample', {})
    top = smp['size'][2] if smp.get('shape') == 'box' else 0.0
    return ind.get('axis_x', 0.0), ind.get('axis_y', 0.0), top

def load(path):
    h = h5py.File(path, 'r')
    P = h['particles']; B = h['bonds']
    d = dict(step=int(h.attrs['step']), time=float(h.attrs['time']))
    c = h['controller'][...].ravel(); d['F'] = abs(c[13]) * 1e-3; d['tipz'] = c[2]; d['maxF'] = c[6] * 1e-3
    x = P['position'][...].reshape(-1, 3); x0 = P['initial_position'][...].reshape(-1, 3)
    i = B['i'][...].ravel(); j = B['j'][...].ravel()
    l0 = B['rest_length'][...].ravel(); E = B['young'][...].ravel()
    er = B['reference_strain'][...].ravel(); slip = B['slip'][...].ravel()
    l = np.linalg.norm(x[j] - x[i], axis=1)
    eps = (l - l0) / l0
    d['sigma_c'] = -E * (eps - er)
    d['slip'] = slip
    ax, ay, top = frame(path)
    m0 = 0.5 * (x0[i] + x0[j]) - np.array([ax, ay, top]); d['m0'] = m0
    d['R'] = np.linalg.norm(m0, axis=1); d['depth'] = -m0[:, 2]; d['rho'] = np.hypot(m0[:, 0], m0[:, 1])
    d['i'] = i; d['j'] = j; d['broken'] = B['broken'][...].ravel()
    d['x'] = x; d['x0'] = x0
    return d

if __name__ == '__main__':
    d = load(sys.argv[1])
    s = d['slip'] > 0
    print('step', d['step'], 't', d['time'], 'slipped', s.sum(), 'max depth', d['depth'][s].max() if s.any() else 0,
          'max rho', d['rho'][s].max() if s.any() else 0, 'max R', d['R'][s].max() if s.any() else 0)
