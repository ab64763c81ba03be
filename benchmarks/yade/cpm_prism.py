# YADE CPM model of the study's plain prism (68 x 68 x 600 mm) in direct tension, for the
# side-by-side cost comparison of benchmarks/side_by_side.sh. Run by YADE, one thread:
#     yade -j1 -n -x benchmarks/yade/cpm_prism.py RADIUS_M OUT_JSON
# Spheres on a regular hexagonal packing of radius RADIUS_M fill the prism; initial contacts
# reach 1.5 radii (the CPM convention), then detection returns to touching spheres. The ends
# are pulled apart by UniaxialStrainer at a strain rate that is quasi-static for CPM
# (the peak moves by well under 2 % when it is halved). The run stops when the stress has
# fallen to 30 % of the peak. Printed and written: spheres, mean real interactions, steps,
# wall time, peak stress and ns per contact-step (wall / (steps x mean interactions)).
import json
import math
import sys
import time

from yade import pack, utils
from yade.wrapper import *  # noqa: F401,F403  (engine and material classes)

radius = float(sys.argv[1]) if len(sys.argv) > 1 else 0.006
out = sys.argv[2] if len(sys.argv) > 2 else 'yade_cpm_prism.json'
strain_rate = float(sys.argv[3]) if len(sys.argv) > 3 else 0.05

concrete = O.materials.append(CpmMat(young=28e9, poisson=0.2, frictionAngle=math.atan(0.8), sigmaT=2.15e6,
                                     epsCrackOnset=1e-4, relDuctility=30, density=2400))
O.bodies.append(pack.regularHexa(pack.inAlignedBox((0, 0, 0), (0.068, 0.068, 0.6)), radius=radius, gap=0,
                                 material=concrete))
features = utils.uniaxialTestFeatures(axis=2)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5, label='aabb')]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=1.5, label='geom')],
                    [Ip2_CpmMat_CpmMat_CpmPhys()], [Law2_ScGeom_CpmPhys_Cpm()]),
    NewtonIntegrator(damping=0.2),
    UniaxialStrainer(strainRate=strain_rate, axis=2, asymmetry=0, posIds=features['posIds'],
                     negIds=features['negIds'], crossSectionArea=features['area'], blockDisplacements=False,
                     blockRotations=False, setSpeeds=True, label='strainer'),
]
O.dt = 0.8 * utils.PWaveTimeStep()
O.step()
aabb.aabbEnlargeFactor = 1.0
geom.interactionDetectionFactor = 1.0

peak = 0.0
samples = 0
contacts_sum = 0
start = time.time()
while True:
    O.run(200, True)
    stress = strainer.avgStress
    peak = max(peak, stress)
    contacts_sum += sum(1 for i in O.interactions if i.isReal)
    samples += 1
    if peak > 0 and stress < 0.3 * peak:
        break
    if O.iter > 2_000_000:
        break
wall = time.time() - start
mean_contacts = contacts_sum / samples
result = {
    'code': 'yade-cpm',
    'spheres': len(O.bodies),
    'mean_real_interactions': mean_contacts,
    'steps': O.iter,
    'wall_s': wall,
    'peak_stress_Pa': peak,
    'ns_per_contact_step': wall * 1e9 / (O.iter * mean_contacts),
}
print(json.dumps(result))
with open(out, 'w') as f:
    json.dump(result, f, indent=1)
