"""Yardsticks for a trained network on its validation captures: the best single feature and a logistic
regression on all features, so a technical artist sees when the network learned nothing beyond a
trivial rule. Both are fitted on the training captures only (the feature and its sign are chosen
there too) and scored on the validation captures, exactly like the network."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .data import Cloud
from .metrics import roc_auc

MAX_FIT_POINTS = 200_000  # training points used for choosing and fitting (a seeded sample beyond that)
NEWTON_STEPS = 25
RIDGE = 1e-6  # keeps the Newton system solvable when features are collinear or a class is separable


@dataclass(frozen=True)
class Baselines:
    feature: str  # the single feature with the best training ROC-AUC
    feature_sign: int  # +1: higher means "needs a probe"; -1: lower does
    feature_roc_auc: float  # its validation ROC-AUC (pooled over the validation points)
    logistic_roc_auc: float  # validation ROC-AUC of a logistic regression on all features


def _pooled(clouds: Sequence[Cloud]) -> tuple[np.ndarray, np.ndarray]:
    features = np.concatenate([c.features for c in clouds]).astype(np.float64)
    labels = np.concatenate([c.labels for c in clouds]).astype(np.float64)
    return features, labels


def _sample(features: np.ndarray, labels: np.ndarray, seed: int) -> tuple[np.ndarray, np.ndarray]:
    if labels.size <= MAX_FIT_POINTS:
        return features, labels
    keep = np.sort(np.random.default_rng(seed).choice(labels.size, MAX_FIT_POINTS, replace=False))
    return features[keep], labels[keep]


def logistic_regression(features: np.ndarray, labels: np.ndarray) -> tuple[np.ndarray, float]:
    """Weights (F,) and bias of a ridge-regularised logistic regression (Newton's method, standardised inputs)."""
    mean = features.mean(axis=0)
    std = features.std(axis=0)
    std = np.where(std > 0, std, 1.0)
    x = np.hstack([(features - mean) / std, np.ones((features.shape[0], 1))])
    w = np.zeros(x.shape[1])
    for _ in range(NEWTON_STEPS):
        p = 1.0 / (1.0 + np.exp(-np.clip(x @ w, -30.0, 30.0)))
        gradient = x.T @ (p - labels) + RIDGE * labels.size * w
        hessian = (x * (p * (1 - p))[:, None]).T @ x + RIDGE * labels.size * np.eye(x.shape[1])
        step = np.linalg.solve(hessian, gradient)
        w -= step
        if np.max(np.abs(step)) < 1e-8:
            break
    weights = w[:-1] / std
    return weights, float(w[-1] - weights @ mean)


def baselines(train: Sequence[Cloud], validation: Sequence[Cloud], seed: int = 0) -> Baselines:
    names = train[0].feature_names
    fit_x, fit_y = _sample(*_pooled(train), seed)
    training_auc = np.array([roc_auc(fit_y, fit_x[:, f]) for f in range(fit_x.shape[1])])
    strength = np.nan_to_num(np.abs(training_auc - 0.5), nan=-1.0)  # a constant feature gives NaN: never chosen
    best = int(np.argmax(strength))
    sign = 1 if training_auc[best] >= 0.5 else -1
    weights, bias = logistic_regression(fit_x, fit_y)
    check_x, check_y = _pooled(validation)
    return Baselines(feature=names[best], feature_sign=sign, feature_roc_auc=roc_auc(check_y, sign * check_x[:, best]),
                     logistic_roc_auc=roc_auc(check_y, check_x @ weights + bias))
