"""The extraction loop as a learning environment, with Gymnasium's API
(``reset``, ``step`` returning ``obs, reward, terminated, truncated,
info``) and no dependency on it: the agent plays the regression model's
part. See docs/python.md for the observation, the action and the reward.
"""

import numpy as np

from . import Mesher, QuadexError

#: Reward of a step whose element the guard had to replace (another type,
#: a corrected Pn, the rule-based element): the element's score less this.
REPLACED_PENALTY = 1.0
#: Reward of a step that passed the observed reference point over (the
#: action's element was refused or too poor, and another reference point
#: was taken), and of a step that failed.
PASSED_OVER_REWARD = -1.0
#: Remedies that keep the action's element: as given, Pn drawn to the size
#: field, Pn snapped onto a front node.
KEPT = ("none", "rescaled", "snapped")


class QuadexEnv:
    """One boundary meshed by element extraction, the agent giving each
    element as the model would: ``action = [type, xn, yn]`` (type rounded
    to 0, 1 or 2; Pn in the reference point's normalised frame).

    ``source``, ``model`` and the options are ``quadex.Mesher``'s; the
    model answers where the agent is not asked (``model_action``) and the
    rule-based fallbacks stay the engine's. ``max_steps`` truncates an
    episode after that many agent steps.
    """

    metadata = {"render_modes": []}

    def __init__(self, source, model="default", max_steps=None, **options):
        self.source = source
        self.model = model
        self.options = options
        self.max_steps = max_steps
        self.mesher = None
        self._obs_dim = None
        self.observation_space = None
        self.action_space = None
        try:
            from gymnasium import spaces

            self.action_space = spaces.Box(
                low=np.array([0.0, -4.0, -4.0]), high=np.array([2.0, 4.0, 4.0]), dtype=np.float64
            )
        except ImportError:
            pass

    def _observe(self):
        self._last = self.mesher.observe()
        if self._last["normalised"] is None:
            return np.zeros(self._obs_dim or 0)
        obs = self._last["normalised"].reshape(-1)
        self._obs_dim = len(obs)
        return obs

    def _advance(self):
        """Takes the engine's own steps that are not element steps
        (closures, seams, transitions, splits, fills) until the next
        element step or the end; returns their kinds."""
        kinds = []
        while not self.mesher.done:
            kind = self.mesher.observe()["kind"]
            if kind == "Element" or kind is None:
                break
            kinds.append(self.mesher.step()["kind"])
        return kinds

    def reset(self, seed=None, options=None):
        """A new episode over the boundary: the engine's steps up to the
        first element step. Returns ``obs, info``."""
        self.mesher = Mesher(self.source, model=self.model, **self.options)
        self.agent_steps = 0
        auto = self._advance()
        obs = self._observe()
        if self.observation_space is None:
            try:
                from gymnasium import spaces

                self.observation_space = spaces.Box(-np.inf, np.inf, shape=obs.shape, dtype=np.float64)
            except ImportError:
                pass
        return obs, {"auto_steps": auto, "observation": self._last}

    def model_action(self):
        """The model's own element at the observed reference point, as an
        action: stepping with it gives the mesh ``quadex mesh`` makes."""
        p = self.mesher.predict()
        return np.array([p["type"], p["pn"][0], p["pn"][1]], dtype=np.float64)

    def step(self, action):
        """Takes the engine's step with ``action`` as the model's element at
        the observed reference point, then the engine's own steps that are
        not element steps. Returns ``obs, reward, terminated, truncated,
        info``; ``info`` holds the step's report and the mesh's quality at
        the end."""
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        t = int(np.clip(np.rint(a[0]), 0, 2))
        info = {}
        try:
            r = self.mesher.step_as(t, (a[1], a[2]))
            reward = self.reward(r)
            info["report"] = r
            info["auto_steps"] = self._advance()
        except QuadexError as e:
            obs = np.zeros(self._obs_dim or 0)
            return obs, PASSED_OVER_REWARD, True, False, {"error": str(e)}
        self.agent_steps += 1
        terminated = self.mesher.done
        truncated = (not terminated and self.max_steps is not None
                     and self.agent_steps >= self.max_steps)
        obs = self._observe()
        if terminated:
            info["quality"] = self.mesher.quality()
        return obs, reward, terminated, truncated, info

    @staticmethod
    def reward(r):
        """The reward of a step's report (docs/python.md): the guard's score
        of the element committed at the observed reference point (the
        quad's quality and the front it leaves, in [0, 1]) when the action
        was kept; less ``REPLACED_PENALTY`` when the guard replaced it;
        ``PASSED_OVER_REWARD`` when the reference point was passed over."""
        if not r.get("at_observed"):
            return PASSED_OVER_REWARD
        score = r.get("score") or 0.0
        if r["remedy"] in KEPT:
            return score
        return score - REPLACED_PENALTY

    def to_meshio(self):
        """The mesh of the episode (finished once done)."""
        return self.mesher.to_meshio()
