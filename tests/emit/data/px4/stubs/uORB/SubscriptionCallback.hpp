// Test stub: uORB::SubscriptionCallbackWorkItem, bound to a work item.
#pragma once

#include "uORB.h"
#include <px4_platform_common/px4_work_queue/ScheduledWorkItem.hpp>

namespace uORB
{
class SubscriptionCallbackWorkItem
{
public:
	SubscriptionCallbackWorkItem(px4::ScheduledWorkItem *item, const orb_metadata *meta) : _item(item), _meta(meta) {}
	bool registerCallback() { return _item != nullptr && _meta != nullptr; }
private:
	px4::ScheduledWorkItem *_item;
	const orb_metadata *_meta;
};
}
