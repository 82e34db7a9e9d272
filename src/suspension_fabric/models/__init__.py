"""Models: the Gillissen-Wilson fabric model and its modification, the fabric-model and
stress-relation interfaces with their plug-ins (any model of d<nn>/dgamma and any stress relation),
and fits.json, the file of the models' steady fits. Held against the simulations in
:mod:`suspension_fabric.evaluation`.

Imports only :mod:`suspension_fabric.io` and :mod:`suspension_fabric.analysis`.
"""
