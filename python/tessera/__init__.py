"""tessera: 3D discontinuum mechanics from Python (docs/python.md).

The compiled module tessera._tessera holds the bindings; this package re-exports them under the
C++ names: tessera.geometry, tessera.law, tessera.zones, tessera.blocks, tessera.contact,
tessera.bc, tessera.reinforcement (steel bars), tessera.quantity, tessera.stop, tessera.recorders,
tessera.instances, tessera.io
(checkpoints, Neper .tess), tessera.calibration (calibrated.json), tessera.solver_options,
tessera.aabb and tessera.Error (tessera::error; InvalidInput, GeometryError, IoError,
NumericalInstability derive from it); tessera.run_record writes run.json.
"""
from ._tessera import (  # noqa: F401
    Error,
    GeometryError,
    InvalidInput,
    IoError,
    NumericalInstability,
    __version__,
    aabb,
    bc,
    blocks,
    calibration,
    contact,
    contact_state,
    energy_balance,
    geometry,
    instances,
    io,
    law,
    mass_scaling_report,
    node_group,
    node_set,
    out_of_balance,
    quantity,
    recorders,
    reinforcement,
    run_result,
    solver_options,
    stop,
    zones,
)
from ._tessera import _arch_reference, _tension_reference  # noqa: F401  (C++ runs, for the tests)
from .run_record import run_record  # noqa: F401
