"""Models: the Gillissen-Wilson fabric model and its modification, the fabric-model and
stress-relation interfaces with their plug-ins (any model of d<nn>/dgamma and any stress relation),
and fits.json, the file of the models' steady fits. Held against the simulations in
[`suspension_fabric.evaluation`][suspension_fabric.evaluation].

Imports only [`suspension_fabric.io`][suspension_fabric.io] and
[`suspension_fabric.analysis`][suspension_fabric.analysis].
"""
