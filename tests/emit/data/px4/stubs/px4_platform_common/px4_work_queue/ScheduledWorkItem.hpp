// Test stub: px4::ScheduledWorkItem with its pure virtual Run().
#pragma once

namespace px4
{
class ScheduledWorkItem
{
public:
	virtual ~ScheduledWorkItem() = default;
	virtual void Run() = 0;
};
}
