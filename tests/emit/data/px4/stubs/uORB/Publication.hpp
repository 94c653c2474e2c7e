// Test stub: uORB::Publication<T>.
#pragma once

#include "uORB.h"

namespace uORB
{
template<typename T>
class Publication
{
public:
	explicit Publication(const orb_metadata *meta) : _meta(meta) {}
	bool publish(const T &data) { (void)data; return _meta != nullptr; }
private:
	const orb_metadata *_meta;
};
}
