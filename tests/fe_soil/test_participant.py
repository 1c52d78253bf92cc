"""The FE soil as a participant, driven through the SDK's session as the
master drives it: its configuration errors name the key, ss-xx is refused
naming ss-xt, the receivers' channels follow the naming rule, statics
answers the same forces with the same displacements bit for bit (what the
master's coupled static iteration needs to stop), a restored step repeats
bitwise, and two MPI ranks give what one gives (1e-7 relative)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import support  # noqa: F401  (skips without dolfinx; puts the checkout on the path)

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "sdk", "python"))
from mpi4py import MPI  # noqa: E402
from railcosim_sdk import progress  # noqa: E402
from railcosim_sdk.session import Session  # noqa: E402
from railcosim_sdk.wire import E, PROTOCOL_VERSION, ProtocolError, pb  # noqa: E402

from fe_soil.participant import Core, FESoilParticipant, follow  # noqa: E402

OWN = '''model = "fe"
mesh_size = 0.5
depth = 4.0
margin = 2.0
receivers = [1.0, 2.5]
[[layers]]
thickness = 1.0
density = 1800.0
shear_wave_speed = 150.0
poisson = 0.33
damping = 0.03
[[layers]]
density = 2000.0
shear_wave_speed = 250.0
poisson = 0.33
damping = 0.02
'''
N = 6
H = 1e-3


def session(core, own=OWN, receives=(3,), output_dir=None):
    p = FESoilParticipant(core, output_dir)
    s = Session(p, None, "test", None)
    s.handle(pb.Envelope(id=1, hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                                               participant="soil")))
    c = pb.Configure(participant="soil", macro_step=H, end_time=1.0, micro_steps=1,
                     own_config=own)
    i = c.interfaces.add(cut="ss", peer="track", x=[0.3 + 0.6 * k for k in range(N)],
                         receives=list(receives), sends=[1, 2])
    for k in range(N):
        i.footprints.add(x=0.3 + 0.6 * k, y=0.65, z=0.0, length=0.6, width=1.3)
    return p, s, s.handle(pb.Envelope(id=2, configure=c))


def forces(values):
    d = pb.CouplingData()
    d.interfaces.add(force=values)
    return d


def drive(core):
    """Statics, initialize, 12 steps of a moving load; the outputs."""
    p, s, _ = session(core)
    load = [4e4 * (1.0 + 0.1 * k) for k in range(N)]
    w0 = s.handle(pb.Envelope(id=3, statics=pb.Statics(inputs=forces(load))))
    s.handle(pb.Envelope(id=4, initialize=pb.Initialize(inputs=forces(load))))
    out = {"statics": list(w0.outputs.data.interfaces[0].displacement), "steps": []}
    for k in range(12):
        f = [4e4 + 3e4 * np.exp(-((j * 0.6 - 0.3 * k) ** 2)) for j in range(N)]
        r = s.handle(pb.Envelope(id=5 + k, step=pb.Step(step=k, h=H, inputs=forces(f))))
        rep = r.step_report
        out["steps"].append(list(rep.outputs.interfaces[0].displacement) +
                            list(rep.outputs.interfaces[0].velocity) + list(rep.history))
    return p, s, out


class Participant(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.core = Core(MPI.COMM_WORLD)

    def refused(self, own, code, text, receives=(3,)):
        with self.assertRaises(ProtocolError) as e:
            session(self.core, own, receives)
        self.assertEqual(e.exception.code, code)
        self.assertIn(text, str(e.exception))

    def test_configuration_errors_name_the_key(self):
        self.refused(OWN.replace("mesh_size", "mesh_sise"), E.BAD_REQUEST,
                     "[soil] mesh_sise is not a key of the FE soil")
        self.refused(OWN.replace("shear_wave_speed = 250.0", "shear_wave_speed = -250.0"),
                     E.BAD_REQUEST, "[soil] layers[2].shear_wave_speed must be > 0 (got -250)")
        self.refused(OWN.replace("poisson = 0.33\ndamping = 0.03", "poisson = 0.5\ndamping = 0.03"),
                     E.BAD_REQUEST, "[soil] layers[1].poisson must be < 0.5 (got 0.5)")
        self.refused('model = "fe"\n', E.BAD_REQUEST, "[soil] layers is missing")
        self.refused(OWN.replace("depth = 4.0", "depth = 1.0"), E.BAD_REQUEST,
                     "[soil] depth 1 m must exceed the layers above the last one (1 m)")
        self.refused(OWN.replace("receivers = [1.0, 2.5]", "receivers = []"), E.BAD_REQUEST,
                     "[soil] receivers must be a list of one or more numbers")

    def test_ss_xx_is_refused_naming_ss_xt(self):
        self.refused(OWN, E.BAD_INTERFACE, "the FE soil serves the ss-xt exchange only",
                     receives=(1, 2))

    def test_channels_statics_and_restore(self):
        p, s, r = session(self.core)
        self.assertEqual(list(r.configured.history), ["r1m_vz_mps", "r2p5m_vz_mps"])
        self.assertEqual(list(r.configured.results)[0], "soil_m")
        load = forces([5e4] * N)
        a = s.handle(pb.Envelope(id=3, statics=pb.Statics(inputs=load))).outputs.SerializeToString()
        b = s.handle(pb.Envelope(id=4, statics=pb.Statics(inputs=load))).outputs.SerializeToString()
        self.assertEqual(a, b, "statics of the same forces twice")
        s.handle(pb.Envelope(id=5, initialize=pb.Initialize(inputs=load)))
        state = s.handle(pb.Envelope(id=6, save=pb.Save())).state
        step = pb.Envelope(id=7, step=pb.Step(step=0, h=H, inputs=forces([9e4] * N)))
        first = s.handle(step).step_report.SerializeToString()
        s.handle(pb.Envelope(id=8, restore=pb.Restore(state=state)))
        again = s.handle(step).step_report.SerializeToString()
        self.assertEqual(first, again, "a step after restore")

    def test_measures_written_to_the_output_folder(self):
        with tempfile.TemporaryDirectory() as tmp:
            p, s, out = drive(self.core)
            p.output_dir = tmp
            res = s.handle(pb.Envelope(id=99, get_results=pb.GetResults())).results
            self.assertEqual([len(f.values) for f in res.fields], [N, 2, 2, 2])
            with open(os.path.join(tmp, "vibration.csv")) as f:
                rows = [line.split(",") for line in f.read().split("\n") if line]
            self.assertEqual(rows[0][:4], ["receiver", "x_m", "y_m", "ppv_mps"])
            self.assertEqual([r[0] for r in rows[1:]], ["r1m_vz_mps", "r2p5m_vz_mps"])
            ppv = [float(r[3]) for r in rows[1:]]
            self.assertEqual(ppv, [float("%.9g" % v) for v in res.fields[2].values])
            self.assertGreater(ppv[0], ppv[1])  # nearer, stronger
            with open(os.path.join(tmp, "receivers.csv")) as f:
                self.assertEqual(len(f.read().split("\n")), 1 + 12 + 1)

    def test_statics_shows_its_cg_iterations_as_progress(self):
        """static_iterations counts every CG iteration (the monitor is
        called at iterations 0 to n of each solve), and the SDK's progress
        thread gets the GIL while a solve runs: frames go out, step -1,
        their counts growing. Asked every millisecond here, so that the
        small block's solve gives several (the master asks every 100 ms)."""
        p, s, _ = session(self.core)
        sent = []
        s.master = type("Master", (), {"send": lambda _self, frame: sent.append(frame)})()
        s.progress_ms = 1
        interval = progress.MIN_INTERVAL_MS
        progress.MIN_INTERVAL_MS = 1
        self.addCleanup(setattr, progress, "MIN_INTERVAL_MS", interval)
        # The GIL changes hands at the monitor's Python code no sooner than
        # the switch interval (5 ms): shorter here, for a short solve.
        self.addCleanup(sys.setswitchinterval, sys.getswitchinterval())
        sys.setswitchinterval(1e-4)
        s.request_id = 3
        s.handle(pb.Envelope(id=3, statics=pb.Statics(inputs=forces([5e4] * N))))
        first = p.soil.ksp.getIterationNumber() + 1
        self.assertEqual(p.static_iterations, first)
        s.request_id = 4
        s.handle(pb.Envelope(id=4, statics=pb.Statics(inputs=forces([6e4] * N))))
        self.assertEqual(p.static_iterations, first + p.soil.ksp.getIterationNumber() + 1)
        self.assertGreater(len(sent), 0, "no progress frame while the static solves ran")
        self.assertTrue(all(f.progress.step == -1 for f in sent))
        self.assertTrue(all(f.id in (3, 4) for f in sent))
        counts = [f.progress.micro_steps for f in sent]
        self.assertEqual(counts, sorted(set(counts)))
        self.assertLessEqual(counts[-1], p.static_iterations)

    def test_two_ranks_agree_with_one(self):
        one = drive(self.core)[2]
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "two.json")
            env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMPI_MCA_rmaps_base_oversubscribe="1")
            proc = subprocess.run([shutil.which("mpirun"), "-n", "2", sys.executable, __file__,
                                   "--write", path], env=env, capture_output=True, text=True,
                                  timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr[-2000:])
            with open(path) as f:
                two = json.load(f)
        for key in one:
            a, b = np.array(one[key]), np.array(two[key])
            np.testing.assert_allclose(b, a, rtol=1e-7, atol=1e-7 * np.max(np.abs(a)), err_msg=key)


if __name__ == "__main__":
    if "--write" in sys.argv:
        core = Core(MPI.COMM_WORLD)
        if MPI.COMM_WORLD.rank != 0:
            follow(core)
        else:
            result = drive(core)[2]
            core.release()
            with open(sys.argv[sys.argv.index("--write") + 1], "w") as f:
                json.dump(result, f)
    else:
        unittest.main()
