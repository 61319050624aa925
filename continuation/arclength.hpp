#pragma once
// A model-independent path follower for G(x, lambda) = 0 (placeholder; see continuation/README.md).
