// Test stub: uORB::Subscription.
#pragma once

#include "uORB.h"

namespace uORB
{
class Subscription
{
public:
	explicit Subscription(const orb_metadata *meta) : _meta(meta) {}
	bool updated() { return _meta != nullptr; }
private:
	const orb_metadata *_meta;
};
}
