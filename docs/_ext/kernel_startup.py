# Kernel start-up for the documentation build only (conf.py copies it into IPYTHONDIR): the
# library draws on matplotlib's Agg backend, so after each cell the open pyplot figures are
# displayed as PNG and closed, as the inline backend would do in Jupyter.
from IPython import get_ipython
from IPython.display import display


def _show_figures(*_):
    import sys

    if "matplotlib.pyplot" not in sys.modules:
        return
    import matplotlib.pyplot as plt

    for number in plt.get_fignums():
        display(plt.figure(number))
    plt.close("all")


_shell = get_ipython()
if _shell is not None:
    from IPython.core.pylabtools import select_figure_formats

    select_figure_formats(_shell, {"png"})
    _shell.events.register("post_execute", _show_figures)
