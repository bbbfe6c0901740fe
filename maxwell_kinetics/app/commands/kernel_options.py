"""The command line's kernel options, read from the kernel registry (:mod:`particles.kernels`).

``--kernel NAME`` chooses a registered kernel that the command carries (``--rate NAME`` is its
alias, kept for one release); every parameter a carried kernel declares
(:class:`particles.kernels.KernelParameter`) becomes an option ``--NAME`` whose help shows its
range and default.  The options are built when the parser is built, so a kernel registered by
the user's code before :func:`maxwell_kinetics.app.cli.main` runs is offered like a built-in.
"""

from __future__ import annotations

import argparse

from particles.validation import InvalidArgumentError, check_real

__all__ = ["solvable", "add_kernel_options", "chosen_kernel", "kernel_from_args",
           "declared_parameters"]


def solvable(cls) -> bool:
    """Whether some method of :mod:`maxwell_kinetics.methods` carries a kernel class (what
    ``solve`` and ``fixed-point`` accept).

    Parameters
    ----------
    cls : type
        A kernel class.

    Returns
    -------
    bool
    """
    from ...methods import carrying_methods

    return bool(carrying_methods(cls))


def declared_parameters(carried) -> dict[str, tuple]:
    """Every parameter declared by a kernel that ``carried`` accepts, with the kernels that
    declare it.

    Parameters
    ----------
    carried : callable
        kernel class → bool.

    Returns
    -------
    dict
        parameter name → (the first declaration, tuple of kernel names).
    """
    from particles.kernels import KERNELS

    out: dict[str, tuple] = {}
    for name, cls in KERNELS.items():
        if not carried(cls):
            continue
        for parameter in cls.parameters:
            first, names = out.get(parameter.name, (parameter, ()))
            out[parameter.name] = (first, names + (name,))
    return out


def add_kernel_options(p, carried, default: str, what: str) -> None:
    """Add ``--kernel`` (alias ``--rate``) and the carried kernels' parameters to a parser.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The subcommand's parser.
    carried : callable
        kernel class → bool: the kernels the command carries.
    default : str
        The default kernel's name.
    what : str
        What the command does with the kernel, for the help.
    """
    from particles.kernels import KERNELS

    names = [name for name, cls in KERNELS.items() if carried(cls)]
    listed = "; ".join(f"{name} (time {KERNELS[name].time_name})" for name in names)
    p.add_argument("--kernel", default=None,
                   help=f"collision kernel of the registry ({what}): {listed}; default "
                   f"{default} (maxwell-kinetics kernels lists them)")
    p.add_argument("--rate", default=None,
                   help="alias of --kernel, kept for one release")
    p.set_defaults(default_kernel=default)
    for name, (parameter, owners) in declared_parameters(carried).items():
        option = "--" + name.replace("_", "-")
        try:
            p.add_argument(option, dest=name, default=None,
                           help=f"--kernel {' or '.join(owners)}: {parameter.doc}, in "
                           f"[{parameter.low:g}, {parameter.high:g}] (default "
                           f"{parameter.default:g})")
        except argparse.ArgumentError:  # the command has an option of that name: it is read
            pass


def chosen_kernel(args, carried):
    """The kernel class that ``--kernel`` (or its alias ``--rate``) names, the default when
    neither is given.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options.
    carried : callable
        kernel class → bool: the kernels the command carries.

    Returns
    -------
    type
        The registered kernel class.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the option typed (``kernel`` or ``rate``) for a name not registered or not
        carried, with the accepted names; naming ``rate`` when both are given.
    """
    from particles.kernels import KERNELS, kernel_class

    if args.kernel is not None and args.rate is not None:
        raise InvalidArgumentError("rate", args.rate, "--kernel or its alias --rate, not both")
    option, name = (("rate", args.rate) if args.rate is not None
                    else ("kernel", args.kernel if args.kernel is not None
                          else args.default_kernel))
    cls = kernel_class(name, option,
                       among=tuple(n for n, c in KERNELS.items() if carried(c)))
    args.kernel, args.rate = cls.name, None  # chosen once: later readers see --kernel
    return cls


def kernel_from_args(args, carried, restitution: float, typed: dict | None = None):
    """The kernel the options name, with its declared parameters as typed.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options (``args.kernel`` and one attribute per declared parameter).
    carried : callable
        kernel class → bool: the kernels the command carries.
    restitution : float
        r, already read.
    typed : dict, optional
        Filled with name → (value read, text) for each parameter given (error messages show
        the text typed).

    Returns
    -------
    particles.kernels.Kernel

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel`` for a name not registered or not carried (the accepted names
        listed), a parameter option given that the chosen kernel does not declare, or a
        parameter out of its range (the text typed shown).
    """
    cls = chosen_kernel(args, carried)
    own = {parameter.name for parameter in cls.parameters}
    values = {}
    typed = {} if typed is None else typed
    for name, (_, owners) in declared_parameters(carried).items():
        text = getattr(args, name, None)
        if text is None:
            continue
        option = name.replace("_", "-")
        if name not in own:
            raise InvalidArgumentError(option, text, f"no --{option} with --kernel "
                                       f"{cls.name} (it belongs to --kernel "
                                       f"{' or '.join(owners)})")
        values[name] = check_real(text, option)
        typed[name] = (values[name], text)
    try:
        return cls(restitution, **values)
    except InvalidArgumentError as exc:
        read = typed.get(exc.name)
        if read is not None and exc.value == read[0]:
            raise InvalidArgumentError(exc.name.replace("_", "-"), read[1],
                                       exc.expected) from None
        raise
