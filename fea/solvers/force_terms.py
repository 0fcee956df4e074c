"""Force terms of the explicit step: one contract for every element kind and every load.

The step loop (:mod:`ccedi.fea.solvers.explicit`) knows no element kind and no load. Each
step it zeroes the internal and the external nodal forces, lets every term add its own,
and combines what the terms return; adding an element kind or a load means writing its
kernel and its data and adding a term to the tuples the run builds
(``explicit._internal_forces``, ``explicit._external_forces``), not editing the loop.

**Internal force terms** (:data:`ForceTerm`): an element kind is a kernel and its data::

    kernel(x, v, data, material, f_int) -> (dt_stable, w_int, w_hg, p_bulk, bad)

It ADDS the term's internal nodal forces at positions x and velocities v [N] to f_int
and returns the smallest critical step of its elements [s] (inf: no limit), their stored
energy [J], their hourglass energy [J], the bulk-viscous power to book for the step [W]
and -1, or the index of its first failed element (the other values and f_int are then to
be discarded). ``material`` is the solids' :data:`SolidMaterial` (a term that does not
need it ignores it). A term with no elements adds nothing and returns
``(inf, 0, 0, 0, -1)``; the step does not call it (the term states its size: a call
passes every array of the data, some 150 ns a term and step). The term also names where
its elements start in the run's error numbering, the status its failure reports, and the
array (if any) its kernel writes the bulk-viscosity part of its forces into: the work of
that part on the mid-step velocity is booked as bulk-viscous dissipation (the
tetrahedra; their kernel then returns ``p_bulk = 0``), which the element power at
v^{n-1/2} overstates when the highest modes ring.

**External force terms** (:data:`ExternalTerm`): a load is a kernel, an impulse and data::

    kernel(t, x, v, data, f_ext) -> None
    impulse(state, nodes, damping, Dt, data, energy) -> None

The kernel ADDS the term's external nodal forces at t^n [N]. The impulse is called once
the trial velocities v^{n+1/2} are known: it may correct them in place (adding the force
that does it to f_ext) and book its works into the step's energy record (Coulomb
friction, :func:`friction_impulse`; :func:`no_impulse` for a load without one).

Every kernel is a numba dispatcher in the compiled run and a plain function (the numpy
reference) with ``backend="numpy"``; the adapters here bring the element modules' kernels
and the contact kernels to the contract. Adding the same numbers in the same order as the
loop did before it knew terms, the run's results are unchanged to the bit.

**Loops over terms.** The terms of a tuple have different types, which numba cannot
iterate over: the step loop is compiled with its loops ``for term in <tuple>:`` written
out, term by term (:func:`unroll_terms`), with each term's kernel (and impulse) called by
name, so that the terms handed to it carry no function objects and numba can cache the
compiled loop on disk (a dispatcher's type is new in every process). numba's own
``literal_unroll`` compiled 1.7 times as long as the written-out loop (its
loop-versioning passes and the larger code they leave), and the loops moved into
compiled functions of their own 2.3 times (each compiled function links and optimises
again the kernels it calls).
"""
import ast
import copy
import inspect
import textwrap
from collections import namedtuple

import numba as nb
import numpy as np

from ccedi.fea.contact.friction import coulomb_friction
from ccedi.fea.contact.penalty import contact_forces
from ccedi.fea.elements import tet4, tet10
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import internal_forces_numpy
from ccedi.fea.elements.hex8_kernels import internal_forces_numba
from ccedi.fea.elements.rod import rod_forces_numba, rod_forces_numpy

W_EXT, E_DAMP, E_BULK, KE, IE, HG, E_PENALTY, W_NORMAL, W_FRICTION = range(9)
# Slots of the step's energy record (9 floats): external work, damping, bulk-viscous
# dissipation, kinetic, internal and hourglass energy, penalty energy, normal and friction
# contact work [J]; the loop books the first six, the contact's impulse the last three.

ForceTerm = namedtuple("ForceTerm", "kernel data size first failure bulk_force")
ForceTerm.__doc__ = """One internal force term of the step (module docstring: the contract).

Attributes
----------
kernel : callable
    ``kernel(x, v, data, material, f_int) -> (dt_stable, w_int, w_hg, p_bulk, bad)``,
    adding to f_int (numba dispatcher, or the numpy reference).
data : tuple
    The term's arrays, as its kernel takes them (a named tuple: the element group).
size : int
    Number of its elements (in the numbering of ``first``); the step skips a term of
    size 0.
first : int
    Index of the term's first element in the numbering its failures are reported in
    (the solid elements: hexahedra, 4-node, 10-node tetrahedra; the rod hinges on
    their own).
failure : int
    Status the step loop returns when the kernel reports a failed element.
bulk_force : (n_nodes, 3) or (0, 3) ndarray
    The array the kernel writes the bulk-viscosity part of its forces into [N], whose
    work on the mid-step velocity is booked as dissipation; empty when the kernel books
    its dissipation through ``p_bulk``.
"""
InternalForces = namedtuple("InternalForces", "terms material")
InternalForces.__doc__ = """The internal force terms of a run and the solids' material.

Attributes
----------
terms : tuple of ForceTerm
    In the order their forces are added (and their failures checked).
material : SolidMaterial
    The solid elements' neo-Hookean constants, handed to every kernel.
"""
ExternalTerm = namedtuple("ExternalTerm", "kernel impulse data size")
ExternalTerm.__doc__ = """One external force term of the step (module docstring: the contract).

Attributes
----------
kernel : callable
    ``kernel(t, x, v, data, f_ext) -> None``, adding the term's forces at t^n to f_ext.
impulse : callable
    ``impulse(state, nodes, damping, Dt, data, energy) -> None``, called on the trial
    velocities v^{n+1/2} (:func:`no_impulse`: nothing to do).
data : tuple
    The term's arrays (a named tuple).
size : int
    Number of loaded rows or nodes; the step skips a term of size 0.
"""
RodGroup = namedtuple("RodGroup", "segments rest_length axial_stiffness hinges bending_stiffness dt_crit")
RodGroup.__doc__ = """Rod elements as :func:`rod_term` takes them.

Attributes
----------
segments : (m, 2) int ndarray
    Rod elements as node index pairs.
rest_length : (m,) ndarray
    Rest lengths [m].
axial_stiffness : (m,) ndarray
    Axial rigidity EA per element [N].
hinges : (h, 3) int ndarray
    Node index triples (i, j, k) of consecutive nodes (bending hinges).
bending_stiffness : (h,) ndarray
    Bending stiffness EI / (l_a + l_b) per hinge [N m].
dt_crit : float
    Smallest critical step of the rods [s] (inf without rods).
"""


hex_term = internal_forces_numba
"""The hexahedra's compiled kernel, which has the internal terms' contract already."""


def hex_term_numpy(x, v, group, material, f):
    """The hexahedra's numpy reference (:func:`ccedi.fea.elements.hex8.internal_forces_numpy`)
    in the contract form; the compiled kernel,
    :func:`ccedi.fea.elements.hex8_kernels.internal_forces_numba`, has it already.

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s].
    group : HexGroup
        The hexahedra.
    material : SolidMaterial
        The solids' constants.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (dt_stable [s], strain energy [J], hourglass energy [J], bulk-viscous power [W],
        -1 or the first inverted element); ``(inf, 0, 0, 0, -1)`` without hexahedra.
    """
    if len(group.hexes):
        return internal_forces_numpy(x, v, group.hexes, b=group.b, volume=group.volume, gamma=group.gamma,
                                     kappa=group.kappa, length_factor=group.length_factor, mu=material.mu,
                                     lam=material.lam, rho=material.rho, c=material.c, f=f)
    return np.inf, 0.0, 0.0, 0.0, -1


@nb.njit(cache=True, fastmath=FASTMATH)
def tet4_term(x, v, group, material, f):
    """The 4-node tetrahedra (:func:`ccedi.fea.elements.tet4.internal_forces_numba`) in the
    contract form: no hourglass energy, and their bulk-viscous dissipation booked from
    ``group.bulk_force`` (so ``p_bulk = 0``).

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s].
    group : Tet4Group
        The tetrahedra.
    material : SolidMaterial
        The solids' constants.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (dt_stable [s], strain energy [J], 0, 0, -1 or the first inverted element).
    """
    dt, w, _, bad = tet4.internal_forces_numba(x, v, group, material, f)
    return dt, w, 0.0, 0.0, bad


def tet4_term_numpy(x, v, group, material, f):
    """:func:`tet4_term` with the numpy reference
    (:func:`ccedi.fea.elements.tet4.internal_forces_numpy`).

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s].
    group : Tet4Group
        The tetrahedra.
    material : SolidMaterial
        The solids' constants.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (dt_stable [s], strain energy [J], 0, 0, -1 or the first inverted element).
    """
    dt, w, _, bad = tet4.internal_forces_numpy(x, v, group, material, f)
    return dt, w, 0.0, 0.0, bad


@nb.njit(cache=True, fastmath=FASTMATH)
def tet10_term(x, v, group, material, f):
    """The 10-node tetrahedra (:func:`ccedi.fea.elements.tet10.internal_forces_numba`) in
    the contract form, as :func:`tet4_term`.

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s].
    group : Tet10Group
        The tetrahedra.
    material : SolidMaterial
        The solids' constants.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (dt_stable [s], strain energy [J], 0, 0, -1 or the first inverted element).
    """
    dt, w, _, bad = tet10.internal_forces_numba(x, v, group, material, f)
    return dt, w, 0.0, 0.0, bad


def tet10_term_numpy(x, v, group, material, f):
    """:func:`tet10_term` with the numpy reference
    (:func:`ccedi.fea.elements.tet10.internal_forces_numpy`).

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s].
    group : Tet10Group
        The tetrahedra.
    material : SolidMaterial
        The solids' constants.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (dt_stable [s], strain energy [J], 0, 0, -1 or the first inverted element).
    """
    dt, w, _, bad = tet10.internal_forces_numpy(x, v, group, material, f)
    return dt, w, 0.0, 0.0, bad


@nb.njit(cache=True, fastmath=FASTMATH)
def rod_term(x, v, rods, material, f):
    """The rods (:func:`ccedi.fea.elements.rod.rod_forces_numba`) in the contract form:
    their critical step is the constant ``rods.dt_crit``; a failure is a hinge folded back
    on itself.

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s] (not used).
    rods : RodGroup
        The rod elements.
    material : SolidMaterial
        Not used.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (rods.dt_crit [s], stretching plus bending energy [J], 0, 0, -1 or the first
        folded hinge).
    """
    w, folded = rod_forces_numba(x, rods.segments, rods.rest_length, rods.axial_stiffness, rods.hinges,
                                 rods.bending_stiffness, f)
    return rods.dt_crit, w, 0.0, 0.0, folded


def rod_term_numpy(x, v, rods, material, f):
    """:func:`rod_term` with the numpy reference (:func:`ccedi.fea.elements.rod.rod_forces_numpy`).

    Parameters
    ----------
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and velocities [m/s] (not used).
    rods : RodGroup
        The rod elements.
    material : SolidMaterial
        Not used.
    f : (n_nodes, 3) ndarray
        Internal forces [N], added to.

    Returns
    -------
    tuple
        (rods.dt_crit [s], stretching plus bending energy [J], 0, 0, -1 or the first
        folded hinge).
    """
    w, folded = rod_forces_numpy(x, rods.segments, rods.rest_length, rods.axial_stiffness, rods.hinges,
                                 rods.bending_stiffness, f)
    return rods.dt_crit, w, 0.0, 0.0, folded


@nb.njit(cache=True, fastmath=FASTMATH)
def contact_term(t, x, v, contact, f_ext):
    """Penalty contact forces (:func:`ccedi.fea.contact.penalty.contact_forces`) in the
    contract form; nothing without slave nodes.

    Parameters
    ----------
    t : float
        Time [s] (not used: the surface is fixed).
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and half-step velocities [m/s].
    contact : ContactGroup
        The slave nodes and the surface; its work arrays receive the contact record.
    f_ext : (n_nodes, 3) ndarray
        External forces [N], added to.
    """
    if contact.nodes.shape[0] > 0:
        contact_forces(x, v, contact, f_ext)


def contact_term_numpy(t, x, v, contact, f_ext):
    """:func:`contact_term` with the reference form of the contact kernel (its plain
    Python ``py_func``).

    Parameters
    ----------
    t : float
        Time [s] (not used).
    x, v : (n_nodes, 3) ndarray
        Nodal positions [m] and half-step velocities [m/s].
    contact : ContactGroup
        The slave nodes and the surface.
    f_ext : (n_nodes, 3) ndarray
        External forces [N], added to.
    """
    if contact.nodes.shape[0] > 0:
        contact_forces.py_func(x, v, contact, f_ext)


@nb.njit(cache=True, fastmath=FASTMATH)
def friction_impulse(state, nodes, damping, Dt, contact, energy):
    """Coulomb friction of the nodes in contact on the trial velocities
    (:func:`ccedi.fea.contact.friction.coulomb_friction`), and the contact's books: the
    normal and friction work of the step added to ``energy[W_NORMAL]``,
    ``energy[W_FRICTION]``, the penalty energy stored in ``energy[E_PENALTY]``.

    Parameters
    ----------
    state : State
        The step's nodal state (``v``, ``v_new`` corrected in place, ``f_ext`` receives
        the friction forces).
    nodes : Nodes
        Masses and free flags of the nodes.
    damping : Damping
        Rayleigh damping (alpha enters the nodes' effective mass).
    Dt : float
        Velocity-update step [s].
    contact : ContactGroup
        The contact of this step (normals and normal forces from :func:`contact_term`).
    energy : (9,) ndarray
        The step's energy record [J].
    """
    if contact.nodes.shape[0] > 0:
        w_n, w_f = coulomb_friction(state.v, state.v_new, state.f_ext, nodes.mass, nodes.free, contact.nodes,
                                    contact.normal, contact.fn, contact.mu, damping.alpha, Dt, contact.out)
        energy[W_NORMAL] += w_n
        energy[W_FRICTION] += w_f
        energy[E_PENALTY] = contact.out[3]


@nb.njit(cache=True, fastmath=FASTMATH)
def no_impulse(state, nodes, damping, Dt, data, energy):
    """The impulse of an external term that has none: does nothing.

    Parameters
    ----------
    state : State
        The step's nodal state.
    nodes : Nodes
        The nodes' constants.
    damping : Damping
        Rayleigh damping.
    Dt : float
        Velocity-update step [s].
    data : tuple
        The term's data.
    energy : (9,) ndarray
        The step's energy record [J].
    """



def unroll_terms(func, lengths, *, functions=None, name=None):
    """``func`` with its loops over tuples of terms written out, term by term, for numba.

    numba cannot iterate over a tuple whose items have different types. Every loop
    ``for term in <tuple>:`` of ``func`` (``<tuple>`` an expression such as
    ``internal.terms``) is replaced by ``lengths[<tuple>]`` copies of its body, the i-th
    after ``term = <tuple>[i]``: straight-line code, in which a ``return`` in the body
    returns from the function as it does from the loop. ``func`` itself stays as it is,
    for plain Python (the numpy reference).

    With ``functions``, the i-th copy calls the term's functions by name instead of
    reading them from the term (``term.kernel(...)`` becomes a call of a global bound to
    ``functions[<tuple>][i]["kernel"]``): the terms then need not carry them (None in
    their place), and a function whose arguments hold no function objects can be cached
    on disk by numba (a dispatcher's type is new in every process).

    Parameters
    ----------
    func : callable
        A module-level function.
    lengths : dict
        Number of terms of each tuple, by the tuple's expression as written in the loop
        (``{"internal.terms": 4, "external": 2}``).
    functions : dict, optional
        For each tuple, one ``{field: function}`` per term: the term attributes to bind.
    name : str, optional
        Name of the written-out function (default ``func``'s); a distinct name gives each
        binding its own numba cache entry.

    Returns
    -------
    callable
        The written-out function, with ``func``'s module globals (and the bound functions).

    Raises
    ------
    ValueError
        If a ``for term in`` loop runs over a tuple ``lengths`` does not name, has an
        ``else`` clause, or breaks or continues, or ``functions`` does not give one
        binding per term.
    """
    functions = functions or {}
    bound = {}

    class BindFields(ast.NodeTransformer):
        def __init__(self, names):
            self.names = names

        def visit_Attribute(self, node):
            node = self.generic_visit(node)
            if isinstance(node.value, ast.Name) and node.value.id == "term" and node.attr in self.names:
                return ast.copy_location(ast.Name(self.names[node.attr], ast.Load()), node)
            return node

    class WriteOut(ast.NodeTransformer):
        def visit_For(self, node):
            node = self.generic_visit(node)
            if not (isinstance(node.target, ast.Name) and node.target.id == "term"):
                return node
            tuple_name = ast.unparse(node.iter)
            if tuple_name not in lengths or node.orelse or any(isinstance(n, (ast.Break, ast.Continue))
                                                               for n in ast.walk(node)):
                raise ValueError(f"{func.__name__}: 'for term in {tuple_name}:' cannot be written out (its length "
                                 "is not given, or it has an else clause, a break or a continue)")
            per_term = functions.get(tuple_name)
            if per_term is not None and len(per_term) != lengths[tuple_name]:
                raise ValueError(f"{func.__name__}: {len(per_term)} function bindings for the "
                                 f"{lengths[tuple_name]} terms of {tuple_name}")
            block = []
            for i in range(lengths[tuple_name]):
                block.append(ast.Assign(targets=[ast.Name("term", ast.Store())],
                                        value=ast.Subscript(copy.deepcopy(node.iter), ast.Constant(i), ast.Load())))
                body = copy.deepcopy(node.body)
                if per_term is not None:
                    names = {}
                    for field, function in per_term[i].items():
                        names[field] = f"_{tuple_name.replace('.', '_')}_{i}_{field}"
                        bound[names[field]] = function
                    body = [BindFields(names).visit(statement) for statement in body]
                block.extend(body)
            return block or [ast.Pass()]

    definition = ast.parse(textwrap.dedent(inspect.getsource(func))).body[0]
    definition.decorator_list = []
    definition.name = name or func.__name__
    definition = WriteOut().visit(definition)
    module = ast.fix_missing_locations(ast.Module([definition], []))
    namespace = dict(func.__globals__)
    namespace.update(bound)
    exec(compile(module, inspect.getsourcefile(func), "exec"), namespace)
    return namespace[definition.name]
