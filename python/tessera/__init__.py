"""tessera: 3D discontinuum mechanics from Python (docs/python.md).

The compiled module tessera._tessera holds the bindings; this package re-exports them under the
C++ names: tessera.geometry, tessera.law, tessera.blocks, tessera.contact, tessera.quantity,
tessera.stop, tessera.recorders, tessera.instances, tessera.solver_options and tessera.Error
(tessera::error; InvalidInput, GeometryError, IoError, NumericalInstability derive from it).
"""
from ._tessera import (  # noqa: F401
    Error,
    GeometryError,
    InvalidInput,
    IoError,
    NumericalInstability,
    blocks,
    contact,
    geometry,
    instances,
    law,
    node_group,
    node_set,
    quantity,
    recorders,
    run_result,
    solver_options,
    stop,
)
from ._tessera import _arch_reference  # noqa: F401  (the C++ arch, for the tests)
