"""The default fit of a coarse Capytaine database nobody tuned the identification to.

The database: a box 20 m x 5 m x 2 m (Capytaine 3.0, `mesh_parallelepiped` with 20 x 5 x 3
panels, open top, `generate_lid`), 6 rigid DOFs about the waterplane centre, omega 0.2 .. 4
rad/s in 39 steps, `export_to_wamit` (about 30 s). Its mesh is so coarse that A~_ij and A~_ji
differ by up to 2.1 % of sqrt(|A~_ii A~_jj|) (the import's reciprocity note): more than the
1 % tolerance. The fit must say so, still aim at 1 %, meet the noise floor with a passive
network (the exact check of `fit --json`), and pack without --allow-tolerance-miss. Before:
`pack` refused (order 10, 60 states, 1.8 %).
"""
import json
import subprocess
import sys

import pytest

SCRIPT = """
import sys, pathlib
import numpy as np
import capytaine as cpt
from capytaine.io.wamit import export_to_wamit
out = pathlib.Path(sys.argv[1])
mesh = cpt.mesh_parallelepiped(size=(20.0, 5.0, 2.0), center=(0, 0, -1.0), resolution=(20, 5, 3),
                               missing_sides={"top"}, name="box")
body = cpt.FloatingBody(mesh=mesh, lid_mesh=mesh.generate_lid(z=0.0),
                        dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                        center_of_mass=(0, 0, 0), name="box")
omegas = np.linspace(0.2, 4.0, 39)
problems = [cpt.RadiationProblem(body=body, radiating_dof=d, omega=w, rho=1025, g=9.81)
            for d in body.dofs for w in [*omegas, 0.0, np.inf]]
problems += [cpt.DiffractionProblem(body=body, wave_direction=b, omega=w, rho=1025, g=9.81)
             for b in (0.0, np.pi / 2, np.pi) for w in omegas]
data = cpt.assemble_dataset(cpt.BEMSolver().solve_all(problems, progress_bar=False))
export_to_wamit(data, str(out / "box"), exports=("1", "3"))
"""


@pytest.fixture(scope="module")
def coarse_box(tmp_path_factory):
    out = tmp_path_factory.mktemp("coarse-capytaine-box")
    r = subprocess.run([sys.executable, "-c", SCRIPT, str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return out / "box.1"


def test_the_fit_says_the_noise_floor_and_meets_it(fmu_pack_binary, coarse_box):
    r = subprocess.run([str(fmu_pack_binary), "fit", str(coarse_box), "--json"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    fit = json.loads(r.stdout)
    notes = fit["notes"]
    floor = [n for n in notes if n.startswith("the data's own noise")]
    assert len(floor) == 1, notes
    # Measured: the surge-pitch gap, 1.334 % of sqrt(s_i s_j) in the fit's own scale (the
    # import's note says 2.09 % of the local sqrt(|A~_ii A~_jj|) at 3.9 rad/s).
    assert 0.012 < fit["tolerance"] < 0.015, fit["tolerance"]
    assert fit["tolerance_met"], fit["max_relative_error"]
    # Measured 0.854 % with 52 states (four invariant blocks, each its own order, poles
    # refined under the passivity constraints); before the refinement 1.103 % with 59.
    assert fit["max_relative_error"] <= fit["tolerance"]
    assert fit["states"] <= 52, fit["states"]
    assert fit["passive"] is True
    # The import's own notes travel with the fit's.
    assert any(n.startswith("A~ made symmetric (reciprocity)") for n in notes), notes
    assert any("invariant blocks" in n for n in notes), notes


def test_the_box_packs_into_a_passive_fmu(fmu_pack_binary, coarse_box, tmp_path):
    archive = tmp_path / "Box.fmu"
    r = subprocess.run([str(fmu_pack_binary), "pack", str(coarse_box), "-o", str(archive)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert archive.is_file()
    assert "judged against that noise floor" in r.stdout, r.stdout
